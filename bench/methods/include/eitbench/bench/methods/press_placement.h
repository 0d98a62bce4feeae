#pragma once
// A method's systematic placement error, measured on labelled presses and undone on new ones.
// One-step images put a press far from the electrodes too far out, and on the hydrogel skin also
// turned one way round (docs/real-presses.md): a bias that depends on where the press is put, not
// scatter. The map learns, from the labelled presses, where a press put at found radius r truly
// lies on average: the true radius and the turn, each a Gaussian-kernel regression on the found
// radius (the turn as a mean direction). It is the same all round the sensor: it assumes the bias
// depends on the distance from the centre only, as it does on a disk with evenly spaced electrodes.
#include <Eigen/Core>
#include <vector>

namespace eitbench {

struct PlacementMapOptions {
  // Kernel widths tried, as fractions of the radius; the one with the lowest leave-one-out mean
  // centre error on the labelled presses is kept (the first wins a tie); a press is left out with
  // every press recorded at the same position. Narrow widths follow a bias that changes quickly
  // with the radius, wide ones average over more presses.
  std::vector<double> bandwidths{0.005, 0.01, 0.015, 0.02, 0.03, 0.05, 0.07, 0.1, 0.15, 0.2, 0.3};
  int min_presses = 10;  // fewer labelled presses cannot measure a bias (at least 2)
};

class PlacementMap {
 public:
  // at: where the method put each labelled press; truth: where each press was; radius: the
  // sensor's (both in its unit). InputError("placement map", field) for sizes that disagree,
  // fewer than min_presses, non-finite positions, a bad radius or bandwidth.
  PlacementMap(const std::vector<Eigen::Vector2d>& at, const std::vector<Eigen::Vector2d>& truth,
               double radius, const PlacementMapOptions& options = {});
  // Where a press put at `found` truly lies on average. A press put at the centre itself (none
  // found) stays there: it has no direction to turn.
  Eigen::Vector2d apply(const Eigen::Vector2d& found) const;
  std::vector<Eigen::Vector2d> apply(const std::vector<Eigen::Vector2d>& found) const;
  double bandwidth() const { return bandwidth_; }  // the chosen width, in the sensor's unit
  double leave_one_out_error() const { return loo_error_; }  // its mean centre error
  int presses() const { return static_cast<int>(found_radius_.size()); }

 private:
  // The map at `found` with width h, leaving out every labelled press recorded at `*skip`
  // (null: none).
  Eigen::Vector2d at_width(const Eigen::Vector2d& found, double h,
                           const Eigen::Vector2d* skip) const;

  std::vector<Eigen::Vector2d> truth_;
  std::vector<double> found_radius_, true_radius_, turn_;  // turn: true angle minus found angle
  std::vector<bool> has_direction_;                        // neither put at nor truly at the centre
  double bandwidth_ = 0, loo_error_ = 0;
};

}  // namespace eitbench
