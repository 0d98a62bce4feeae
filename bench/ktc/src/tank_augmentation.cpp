#include "eitbench/bench/ktc/tank_augmentation.h"

#include <Eigen/Core>
#include <cmath>

#include "eitbench/augment/channel_symmetry.h"
#include "eitbench/augment/pattern_symmetry.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

std::vector<GroupElement> ktc_group(const CurrentPatterns& patterns) {
  const MeasurementProtocol protocol("ktc", patterns);
  return protocol_elements(protocol, group_elements(AugmentGroup::dihedral, patterns.electrodes()));
}

ClassImage move_ktc_labels(const ClassImage& labels, const GroupElement& g,
                           const KtcOrientation& orientation) {
  const int n = static_cast<int>(labels.rows());
  const GroupElement back = inverse(g, 32);
  const double w = 2.0 / n;  // the unit square's pixels: the tank's size cancels
  ClassImage moved(labels.rows(), labels.cols());
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector2d q(-1 + (j + 0.5) * w, 1 - (i + 0.5) * w);
      const Eigen::Vector2d q0 =
          orientation.to_image(transform_point(orientation.to_model(q), back, 32));
      const double r = (1 - q0.y()) / w - 0.5, c = (q0.x() + 1) / w - 0.5;
      const long ri = std::lround(r), ci = std::lround(c);
      if (std::abs(r - ri) > 1e-6 || std::abs(c - ci) > 1e-6 || ri < 0 || ci < 0 || ri >= n ||
          ci >= n)
        throw InputError("GroupElement", g.to_string(),
                         "does not map KTC's pixel grid onto itself in this orientation (electrode "
                         "1 off the image's axes): its labels cannot move with it");
      moved(i, j) = labels(ri, ci);
    }
  return moved;
}

KtcSimulatedSet augment_ktc_set(const KtcSimulatedSet& set, const CurrentPatterns& patterns,
                                const std::vector<GroupElement>& elements,
                                const KtcOrientation& orientation) {
  const auto G = static_cast<Eigen::Index>(elements.size());
  std::vector<PatternAction> actions;
  for (const GroupElement& g : elements) actions.push_back(pattern_action(patterns, g));
  KtcSimulatedSet out;
  out.frames.resize(set.frames.rows() * G, set.frames.cols());
  for (Eigen::Index n = 0; n < set.frames.rows(); ++n)
    for (Eigen::Index k = 0; k < G; ++k) {
      out.frames.row(n * G + k) = actions[k].apply(set.frames.row(n).transpose()).transpose();
      out.labels.push_back(move_ktc_labels(set.labels[n], elements[k], orientation));
    }
  return out;
}

}  // namespace eitbench
