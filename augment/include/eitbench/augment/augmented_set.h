#pragma once
// Augmenting a whole set of labelled frames: expanded (every frame times every group element), or
// on the fly (one group element per sample and epoch, drawn deterministically, with no copy).
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "eitbench/augment/channel_symmetry.h"
#include "eitbench/augment/label_transform.h"
#include "eitbench/augment/symmetry.h"
#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench {

// One sample a row. Labels and circles are optional (zero columns / empty vector); when a sample's
// circles are given, its label is transformed exactly by re-rasterising them.
struct LabelledFrames {
  SampleMatrix frames;                       // N x frame size
  SampleMatrix labels;                       // N x pixels, or N x 0
  std::vector<std::vector<Circle>> circles;  // N lists, or empty
  // sigma_0, which re-rasterised labels are relative to: required with circles (no default, so
  // that a set on another scale cannot take the simulated data set's 0.05 by omission).
  double background = NAN;
};

struct AugmentSetup {
  AugmentGroup group = AugmentGroup::dihedral;
  FrameLayout layout = FrameLayout::reduced;
  int electrodes = 16;  // L >= 4, as the protocol needs
  int image_size = 64;  // labels are image_size^2 pixels over [-R, R]^2; at least 1
  double radius = 1.0;  // positive and finite
  // A sensor of another shape (docs/sensors.md): its group, found from the mesh, and the grid
  // covering it, which replace D_L and the disk's grid (image_size and electrodes must agree).
  // `group` then picks among the sensor's elements: dihedral all of them, rotations its rotations,
  // mirror the identity and its first mirror, none the identity; paper is refused. Null: the disk.
  std::shared_ptr<const ShapedSensor> sensor;
  // The protocol the frames are read on (docs/protocols.md): frames are then its inputs and
  // `layout` is not used. Null: the adjacent protocol in `layout`. The paper's column reversal is
  // the adjacent map's only; any other protocol is refused with it.
  std::shared_ptr<const MeasurementProtocol> protocol;
  // Positive: the inputs are not frames but an image's pixels, this many (a one-step
  // reconstruction a post-processing network reads, bench/ktc/tank_network.h). No group acts on
  // them (the set is expanded beforehand, on its frames): `group` must then be none. 0: frames.
  int image_inputs = 0;

  // Throws InputError("AugmentSetup", field) for a value out of range.
  void validate() const;
};

// The elements `setup.group` stands for: group_elements(group, electrodes) on the disk, or the
// sensor's own (see AugmentSetup::sensor). Validates the setup first.
std::vector<GroupElement> augment_elements(const AugmentSetup& setup);
// Values a frame has: image_inputs, the protocol's inputs, or the adjacent layout's size.
int frame_width(const AugmentSetup& setup);
// How each of augment_elements(setup) acts on a frame, in that order: FrameSymmetry's tables for
// the adjacent protocol (the paper's variant included), channel_actions for any other. Throws
// InputError naming the first channel an element cannot map.
std::vector<SignedPermutation> frame_actions(const AugmentSetup& setup);
// The label images' moves: on the disk's grid, or on the sensor's.
ImageSymmetry image_symmetry(const AugmentSetup& setup);

// Validates the setup, then throws InputError("frames", ...) when sizes disagree with it.
void check_labelled_frames(const LabelledFrames& set, const AugmentSetup& setup);

// |G| x N rows, sample-major: row i |G| + k is sample i under group element k.
LabelledFrames expand_by_group(const LabelledFrames& set, const AugmentSetup& setup);

// Shares the set it draws from, so a temporary passed in cannot dangle.
class OnTheFlyAugmenter {
 public:
  OnTheFlyAugmenter(std::shared_ptr<const LabelledFrames> set, const AugmentSetup& setup,
                    std::uint64_t seed);

  int size() const { return static_cast<int>(set_->frames.rows()); }
  const std::vector<GroupElement>& elements() const { return elements_; }
  // The element of sample i in `epoch`: a hash of (seed, epoch, i), uniform over the group.
  const GroupElement& element(int sample, int epoch) const;
  // Sample i under g: its frame, and its label (empty when the set has none; the stored label for
  // the identity, else transformed as moved_label does).
  Eigen::VectorXd frame(int i, const GroupElement& g) const;
  Eigen::VectorXd label(int i, const GroupElement& g) const;
  // Rows of `frames` and `labels` (resized) get samples `indices` as they are in `epoch`.
  void batch(const std::vector<int>& indices, int epoch, SampleMatrix& frames,
             SampleMatrix& labels) const;

 private:
  std::shared_ptr<const LabelledFrames> set_;  // never null
  AugmentSetup setup_;
  std::uint64_t seed_;
  std::vector<GroupElement> elements_;
  std::vector<SignedPermutation> actions_;  // one per element
  ImageSymmetry images_;
};

}  // namespace eitbench
