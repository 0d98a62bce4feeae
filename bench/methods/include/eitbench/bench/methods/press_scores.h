#pragma once
// Where a method puts a real press: the centre error on a press set (measured frames with one
// known touch each, docs/data.md#press-sets-measured-frames-with-known-touches). Each frame's
// located touch is the strongest found (the highest contrast); a frame in which the method finds
// none is located at the sensor's centre, the floor that predicting the centre sets for every
// method, so that finding nothing never scores better than guessing.
#include <cmath>
#include <vector>

#include "eitbench/bench/data/dataset.h"
#include "eitbench/bench/methods/touches.h"

namespace eitbench {

struct PressScores {
  int frames = 0;
  int none_found = 0;  // frames located at the centre for want of a touch
  // Centre error over the frames, in the mesh's unit: median, mean, 90th percentile (linear
  // between order statistics, as the touch metrics).
  double median = NAN, mean = NAN, p90 = NAN;
};

// Where a method puts a press: its strongest found touch (the highest contrast), or `centre`
// when it found none.
Eigen::Vector2d located_press(const std::vector<Touch>& found, const Eigen::Vector2d& centre);
// located_press of every frame, with the sensor's centre (0, 0) for a frame without a touch.
std::vector<Eigen::Vector2d> located_presses(const TouchFrames& found);
// Where each frame's one true press is (InputError otherwise, naming the frame).
std::vector<Eigen::Vector2d> true_presses(const std::vector<std::vector<PressTouch>>& truth);

// One true touch a frame (InputError otherwise, naming the frame), found lists of the same length.
PressScores score_presses(const TouchFrames& found,
                          const std::vector<std::vector<PressTouch>>& truth);
// The same from where each frame's press was put (a method that gives a position, not images).
PressScores score_positions(const std::vector<Eigen::Vector2d>& at,
                            const std::vector<std::vector<PressTouch>>& truth);
// The floor: every frame located at the centre (0, 0).
PressScores centre_floor(const std::vector<std::vector<PressTouch>>& truth);

// Where a band's presses are put against where they are: a method that puts them too far out,
// or turned one way round, shows it here. A systematic error, unlike scatter, is the model's.
struct PressPlacement {
  double true_radius = NAN, found_radius = NAN;  // means over the band, in the mesh's unit
  // The median of (found angle - true angle), counter-clockwise, in degrees within [-180, 180];
  // over the presses neither at nor put at the centre (NaN when there are none). A plain median,
  // not a circular one: it reads a bias of some tens of degrees, not turns near half a turn.
  double turn_degrees = NAN;
};
// The presses whose true distance from the centre (0, 0) lies in [inner, outer) x `radius`, and
// their scores: where on the sensor a method's error comes from. One band a pair of neighbouring
// `edges` (fractions of the radius, ascending, from 0), the last from the last edge on without
// bound, since a press may be recorded a little beyond the rim. A band without presses has
// frames 0 and NaN scores.
struct PressBand {
  double inner = 0, outer = INFINITY;  // fractions of the radius
  PressScores scores;
  PressPlacement placement;
};
// InputError("press bands", field) for a bad radius or edges, or one list a frame too few.
std::vector<PressBand> score_presses_by_distance(const TouchFrames& found,
                                                 const std::vector<std::vector<PressTouch>>& truth,
                                                 double radius,
                                                 const std::vector<double>& edges = {0, 0.5, 0.8});
// The same from where each frame's press was put.
std::vector<PressBand> score_positions_by_distance(
    const std::vector<Eigen::Vector2d>& at, const std::vector<std::vector<PressTouch>>& truth,
    double radius, const std::vector<double>& edges = {0, 0.5, 0.8});

// How an image puts its press: the strongest blob (find_touches) or the centroid of every pixel
// (centroid_touch), at `threshold` x the image's maximum.
struct PressRule {
  bool centroid = false;
  double threshold = 0.5;
};
// The touches an image gives by `rule` (find_touches or centroid_touch), and each row of `images`.
std::vector<Touch> press_touches(const Eigen::VectorXd& image, const PixelGrid& grid,
                                 const PressRule& rule);
TouchFrames press_touches(const SampleMatrix& images, const PixelGrid& grid, const PressRule& rule);
// The rule with the lowest mean centre error on labelled presses, over both kinds and the
// thresholds of TouchOptions; the first wins a tie, the strongest blob before the centroid. The
// identity prior's images favour the centroid, the smooth priors' the blob (docs/real-presses.md).
PressRule choose_press_rule(const SampleMatrix& images, const PixelGrid& grid,
                            const std::vector<std::vector<PressTouch>>& truth);

}  // namespace eitbench
