#include "eitbench/bench/data/augment_file.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "eitbench/augment/augmented_set.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/training_data.h"

namespace eitbench {

long long augment_dataset_file(const std::string& in, const std::string& out,
                               const FileAugmentOptions& o) {
  Dataset data = read_dataset(in);
  const int L = data.electrodes;
  // A set on a sensor of another shape moves by that sensor's group (training_data.h).
  const AugmentSetup setup = sensor_of(data, o.group);
  const std::vector<GroupElement> elements =
      o.elements.empty() ? augment_elements(setup) : o.elements;
  const FrameSymmetry symmetry(L);
  // Another protocol moves by signed channel permutations, its frames and its inputs alike.
  const MeasurementProtocol protocol = measurement_protocol(data);
  // (FrameSymmetry's frame tables are the rotating order's: adjacent-ascending moves by channels.)
  const bool other = !protocol.same_channels(adjacent_protocol(L));
  std::vector<SignedPermutation> frame_moves, input_moves;
  if (other)
    for (const GroupElement& g : elements) {
      frame_moves.push_back(channel_action(protocol, g, true));
      input_moves.push_back(channel_action(protocol, g));
    }
  const ImageSymmetry images = image_symmetry(setup);
  if (setup.sensor)  // a named element the sensor lacks is refused before anything is written
    for (const GroupElement& g : elements) images.move(Eigen::Vector2d::Zero(), g);

  // The writer takes the attributes and the reference from `data` itself (no copy of the samples).
  // A sensor's whole group by its name ("D4"); on the disk the group's ("d16").
  const bool whole = setup.sensor && o.group == AugmentGroup::dihedral;
  data.augmentation = o.elements.size() == 1 ? o.elements.front().to_string()
                      : whole                ? setup.sensor->group.name()
                                             : to_string(o.group);
  // Paired references belong to the input's frames, one each: the expanded set has other rows.
  data.references.resize(0, data.references.cols());
  DatasetWriter writer(out, data, data.has_labels(), !data.circles.empty());
  for (int begin = 0; begin < data.size(); begin += o.block) {
    const int end = std::min(data.size(), begin + o.block);
    // Where each input sample's rows start in this block: chosen samples get |G| rows, others 1.
    std::vector<Eigen::Index> first(end - begin + 1, 0);
    std::vector<char> chosen(end - begin);
    for (int i = begin; i < end; ++i) {
      chosen[i - begin] =
          std::find(o.splits.begin(), o.splits.end(), data.split[i]) != o.splits.end();
      first[i - begin + 1] =
          first[i - begin] + (chosen[i - begin] ? static_cast<Eigen::Index>(elements.size()) : 1);
    }
    const Eigen::Index rows = first.back();
    Dataset block;
    block.frames.resize(rows, data.frames.cols());
    block.differences.resize(rows, data.differences.cols());
    block.labels.resize(rows, data.has_labels() ? data.labels.cols() : 0);
    block.split.resize(static_cast<std::size_t>(rows));
    if (!data.circles.empty()) block.circles.resize(static_cast<std::size_t>(rows));
    // Rows depend on one input sample each: parallel, and the same for any thread count.
    tbb::parallel_for(begin, end, [&](int i) {
      for (Eigen::Index k = 0; k < first[i - begin + 1] - first[i - begin]; ++k) {
        const GroupElement g =
            chosen[i - begin] ? elements[static_cast<std::size_t>(k)] : GroupElement{0, false};
        const Eigen::Index r = first[i - begin] + k;
        const std::size_t e = chosen[i - begin] ? static_cast<std::size_t>(k) : 0;
        if (other && chosen[i - begin]) {
          block.frames.row(r) = frame_moves[e].apply(data.frames.row(i).transpose()).transpose();
          block.differences.row(r) =
              input_moves[e].apply(data.differences.row(i).transpose()).transpose();
        } else if (other) {  // the sample as it is
          block.frames.row(r) = data.frames.row(i);
          block.differences.row(r) = data.differences.row(i);
        } else {
          block.frames.row(r) =
              symmetry.apply(o.group, g, data.frames.row(i).transpose(), FrameLayout::rotating)
                  .transpose();
          block.differences.row(r) =
              symmetry.apply(o.group, g, data.differences.row(i).transpose(), FrameLayout::reduced)
                  .transpose();
        }
        block.split[static_cast<std::size_t>(r)] = data.split[i];
        if (!data.circles.empty())
          block.circles[static_cast<std::size_t>(r)] = images.move(data.circles[i], g);
        if (data.has_labels())
          block.labels.row(r) = moved_label(data.labels.row(i).transpose(),
                                            data.circles.empty() ? nullptr : &data.circles[i],
                                            data.background, g, images)
                                    .transpose();
      }
    });
    writer.append(block);
  }
  writer.commit();
  return writer.size();
}

}  // namespace eitbench
