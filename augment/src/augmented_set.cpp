#include "eitbench/augment/augmented_set.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <numeric>
#include <stdexcept>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/random.h"

namespace eitbench {
namespace {

// Sample i's label under g: exact from its circles when the set has them, bilinear otherwise.
Eigen::VectorXd transformed_label(const LabelledFrames& set, int i, const GroupElement& g,
                                  const ImageSymmetry& images) {
  return moved_label(
      set.labels.cols() > 0 ? Eigen::VectorXd(set.labels.row(i).transpose()) : Eigen::VectorXd(),
      set.circles.empty() ? nullptr : &set.circles[i], set.background, g, images);
}

}  // namespace

void AugmentSetup::validate() const {
  auto fail = [](const char* field, const std::string& why) {
    throw InputError("AugmentSetup", field, why);
  };
  if (electrodes < 4)
    fail("electrodes", "the protocol needs at least 4, got " + std::to_string(electrodes));
  if (image_size < 1) fail("image_size", "must be positive, not " + std::to_string(image_size));
  if (!(radius > 0) || !std::isfinite(radius)) fail("radius", "must be positive and finite");
  if (protocol && protocol->electrodes() != electrodes)
    fail("protocol", "the " + protocol->name() + " protocol has " +
                         std::to_string(protocol->electrodes()) + " electrodes, not " +
                         std::to_string(electrodes));
  if (image_inputs < 0)
    fail("image_inputs", "must not be negative, got " + std::to_string(image_inputs));
  if (image_inputs > 0 && group != AugmentGroup::none)
    fail("group", "no group acts on an image's pixels as inputs: expand the set beforehand");
  if (protocol && group == AugmentGroup::paper && !is_adjacent(*protocol))
    fail("group",
         "the paper's column reversal is defined on the adjacent protocol's map only, not "
         "on the " +
             protocol->name() + " protocol");
  if (sensor) {
    if (sensor->group.electrodes != electrodes)
      fail("sensor", "has " + std::to_string(sensor->group.electrodes) + " electrodes, not " +
                         std::to_string(electrodes));
    if (sensor->grid.size() != image_size)
      fail("sensor", "its grid is " + std::to_string(sensor->grid.size()) + " pixels a side, not " +
                         std::to_string(image_size));
    if (group == AugmentGroup::paper)
      fail("group",
           "the paper's column reversal is the disk's only; a sensor of another shape "
           "augments by its own group");
  }
}

std::vector<GroupElement> augment_elements(const AugmentSetup& setup) {
  setup.validate();
  if (!setup.sensor) return group_elements(setup.group, setup.electrodes);
  // The sensor lists the identity first, then its rotations, then its mirrors.
  std::vector<GroupElement> out;
  for (const GroupElement& g : setup.sensor->group.frame_elements()) {
    const bool identity = g == GroupElement{};
    const bool first_mirror = g.mirror && (out.empty() || !out.back().mirror);
    if (setup.group == AugmentGroup::dihedral ||
        (setup.group == AugmentGroup::rotations && !g.mirror) ||
        (setup.group == AugmentGroup::mirror && (identity || first_mirror)) ||
        (setup.group == AugmentGroup::none && identity))
      out.push_back(g);
  }
  return out;
}

int frame_width(const AugmentSetup& setup) {
  if (setup.image_inputs > 0) return setup.image_inputs;
  return setup.protocol ? setup.protocol->input_size()
                        : static_cast<int>(frame_size(setup.layout, setup.electrodes));
}

std::vector<SignedPermutation> frame_actions(const AugmentSetup& setup) {
  const auto elements = augment_elements(setup);
  if (setup.image_inputs > 0) {  // validate() admits the group none only: the identity
    std::vector<int> same(static_cast<std::size_t>(setup.image_inputs));
    std::iota(same.begin(), same.end(), 0);
    return {{same, std::vector<double>(same.size(), 1.0)}};
  }
  if (setup.protocol && setup.protocol->has_patterns()) {
    // Current patterns move linearly (pattern_action), not by a permutation: only the identity
    // is one. Their augmented sets are expanded beforehand (bench/ktc/tank_augmentation.h).
    if (elements.size() != 1 || elements[0] != GroupElement{})
      throw InputError("AugmentSetup", "group",
                       "the " + setup.protocol->name() +
                           " protocol is given by current patterns: train it with the group none "
                           "on a set expanded by the group beforehand");
    std::vector<int> same(static_cast<std::size_t>(setup.protocol->input_size()));
    std::iota(same.begin(), same.end(), 0);
    return {{same, std::vector<double>(same.size(), 1.0)}};
  }
  if (setup.protocol && !is_adjacent(*setup.protocol))
    return channel_actions(*setup.protocol, elements);
  const FrameLayout layout = setup.protocol ? FrameLayout::reduced : setup.layout;
  const FrameSymmetry symmetry(setup.electrodes);
  std::vector<SignedPermutation> out;
  for (const GroupElement& g : elements) {
    const auto& table = symmetry.table(setup.group, g, layout);
    out.push_back({table, std::vector<double>(table.size(), 1.0)});
  }
  return out;
}

ImageSymmetry image_symmetry(const AugmentSetup& setup) {
  if (setup.sensor) return ImageSymmetry(setup.sensor);
  return ImageSymmetry(setup.electrodes, PixelGrid(setup.image_size, setup.radius));
}

void check_labelled_frames(const LabelledFrames& set, const AugmentSetup& setup) {
  setup.validate();
  const Eigen::Index n = set.frames.rows();
  if (n == 0) throw InputError("frames", "", "the set is empty");
  if (set.frames.cols() != frame_width(setup))
    throw InputError(
        "frames", "columns",
        std::to_string(set.frames.cols()) + " values a frame, but " +
            (setup.protocol ? "the " + setup.protocol->name() + " protocol has " +
                                  std::to_string(frame_width(setup)) + " inputs"
                            : std::to_string(setup.electrodes) + " electrodes in the " +
                                  to_string(setup.layout) + " layout give " +
                                  std::to_string(frame_width(setup))));
  if (!set.frames.allFinite()) throw InputError("frames", "values", "NaN or infinite values");
  if (set.labels.cols() > 0 &&
      (set.labels.rows() != n || set.labels.cols() != setup.image_size * setup.image_size))
    throw InputError("labels", "shape",
                     "labels must be N x " + std::to_string(setup.image_size * setup.image_size));
  if (!set.circles.empty() && static_cast<Eigen::Index>(set.circles.size()) != n)
    throw InputError("circles", "count", "one circle list per frame is needed");
  if (!set.circles.empty() && !(set.background > 0 && std::isfinite(set.background)))
    throw InputError("LabelledFrames", "background",
                     "must be set, positive and finite when circles are given (their labels are "
                     "relative to it)");
}

LabelledFrames expand_by_group(const LabelledFrames& set, const AugmentSetup& setup) {
  check_labelled_frames(set, setup);
  const auto elements = augment_elements(setup);
  const auto actions = frame_actions(setup);
  const ImageSymmetry images = image_symmetry(setup);
  const bool labelled = set.labels.cols() > 0 || !set.circles.empty();
  const Eigen::Index n = set.frames.rows(), k = static_cast<Eigen::Index>(elements.size());
  LabelledFrames out;
  out.background = set.background;
  out.frames.resize(n * k, set.frames.cols());
  if (labelled) out.labels.resize(n * k, images.grid().num_pixels());
  if (!set.circles.empty()) out.circles.resize(n * k);
  // Every output row depends on one input row only: parallel, and identical for any thread count.
  tbb::parallel_for(Eigen::Index(0), n, [&](Eigen::Index i) {
    const Eigen::VectorXd frame = set.frames.row(i).transpose();
    for (Eigen::Index e = 0; e < k; ++e) {
      const GroupElement& g = elements[e];
      out.frames.row(i * k + e) = actions[e].apply(frame).transpose();
      if (labelled)
        out.labels.row(i * k + e) =
            transformed_label(set, static_cast<int>(i), g, images).transpose();
      if (!set.circles.empty()) out.circles[i * k + e] = images.move(set.circles[i], g);
    }
  });
  return out;
}

OnTheFlyAugmenter::OnTheFlyAugmenter(std::shared_ptr<const LabelledFrames> set,
                                     const AugmentSetup& setup, std::uint64_t seed)
    : set_(std::move(set)),
      setup_((setup.validate(), setup)),  // before the tables are built from it
      seed_(seed),
      elements_(augment_elements(setup)),
      actions_(frame_actions(setup)),
      images_(image_symmetry(setup)) {
  if (!set_) throw std::invalid_argument("OnTheFlyAugmenter: no set");
  check_labelled_frames(*set_, setup);
}

const GroupElement& OnTheFlyAugmenter::element(int sample, int epoch) const {
  const std::uint64_t h = mix64(mix64(mix64(seed_) ^ static_cast<std::uint64_t>(epoch)) ^
                                static_cast<std::uint64_t>(sample));
  return elements_[h % elements_.size()];
}

Eigen::VectorXd OnTheFlyAugmenter::frame(int i, const GroupElement& g) const {
  for (std::size_t e = 0; e < elements_.size(); ++e)
    if (elements_[e] == g) return actions_[e].apply(set_->frames.row(i).transpose());
  throw std::invalid_argument("OnTheFlyAugmenter::frame: " + g.to_string() +
                              " is not one of the augmenting elements");
}

Eigen::VectorXd OnTheFlyAugmenter::label(int i, const GroupElement& g) const {
  if (set_->labels.cols() == 0 && set_->circles.empty()) return Eigen::VectorXd();
  if (g == GroupElement{} && set_->labels.cols() > 0)
    return set_->labels.row(i).transpose();  // the identity: the stored label, no re-rasterising
  return transformed_label(*set_, i, g, images_);
}

void OnTheFlyAugmenter::batch(const std::vector<int>& indices, int epoch, SampleMatrix& frames,
                              SampleMatrix& labels) const {
  const bool labelled = set_->labels.cols() > 0 || !set_->circles.empty();
  frames.resize(static_cast<Eigen::Index>(indices.size()), set_->frames.cols());
  labels.resize(static_cast<Eigen::Index>(indices.size()),
                labelled ? images_.grid().num_pixels() : 0);
  for (std::size_t b = 0; b < indices.size(); ++b) {
    const int i = indices[b];
    const GroupElement& g = element(i, epoch);
    frames.row(b) = frame(i, g).transpose();
    if (labelled) labels.row(b) = label(i, g).transpose();
  }
}

}  // namespace eitbench
