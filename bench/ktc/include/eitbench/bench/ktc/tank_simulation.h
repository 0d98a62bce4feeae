#pragma once
// Simulated tanks like KTC2023's (docs/ktc.md#simulated-tanks): one to a few resistive and
// conductive targets of varied shape in the calibrated tank, their difference frames with noise
// like the real frames', and their labels (water 0, resistive 1, conductive 2) on a grid in KTC's
// orientation: the training data of a learned reconstructor for the tank.
#include <Eigen/Core>
#include <random>
#include <vector>

#include "eitbench/bench/ktc/score.h"
#include "eitbench/bench/ktc/segmentation.h"
#include "eitbench/bench/ktc/tank.h"

namespace eitbench {

// A star-shaped target in the model's coordinates (m): its boundary at angle t about the centre
// lies at radius * shape(t), with shape a regular polygon's (corners >= 3), a blob's (1 plus a few
// random harmonics) or 1 (a disc).
struct KtcTarget {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0;
  int cls = 1;      // 1 resistive, 2 conductive
  int corners = 0;  // a polygon's, 0 otherwise
  double phase = 0;
  std::vector<double> harmonics;  // a blob's: cos and sin amplitudes of harmonics 2, 3, ...
  double contrast = 0;  // its conductivity / the background's; 0: the options' for its class

  double boundary(double angle) const;  // radius * shape(angle)
  bool contains(const Eigen::Vector2d& point) const;
};

struct KtcSimulationOptions {
  int samples = 100;
  unsigned seed = 1;
  int max_targets = 3;      // 1 ... max_targets a tank, uniformly
  double smallest = 0.08;   // target radius, as a fraction of the tank's
  double largest = 0.33;    // about a third of the tank, as KTC's largest
  double resistive = 0.01;  // a resistive target's conductivity / the background's
  double conductive = 100;  // a conductive target's
  // Each target's contrast drawn as its class's times spread^u, u uniform in [-1, 1]: a band of
  // contrasts (log-uniform) rather than one. 1: every target at its class's.
  double contrast_spread = 1;
  double noise = 0;            // V, each value's standard deviation (repeated_pattern_noise)
  int grid = 64;               // label pixels across the tank's square
  KtcOrientation orientation;  // the labels' (KTC's, docs/ktc.md#orientation)

  // InputError("KtcSimulationOptions", field) for a value out of range.
  void validate() const;
};

struct KtcSimulatedSet {
  Eigen::MatrixXd frames;                       // samples x values: target minus empty tank
  std::vector<ClassImage> labels;               // grid x grid, row 0 at the top
  std::vector<std::vector<KtcTarget>> targets;  // each sample's
};

// The targets of one tank: inside 0.9 of the tank's radius, apart by 5 % of it, each shape and
// class equally likely.
std::vector<KtcTarget> draw_ktc_targets(std::mt19937_64& rng, const KtcSimulationOptions& options,
                                        double tank_radius);
// Each mesh element's conductivity: the background, or a target's at its centroid.
Eigen::VectorXd ktc_conductivity(const Mesh& mesh, double background,
                                 const std::vector<KtcTarget>& targets,
                                 const KtcSimulationOptions& options);
// The classes on options.grid pixels across [-R, R]^2 in KTC's image coordinates.
ClassImage ktc_labels(const std::vector<KtcTarget>& targets, double tank_radius,
                      const KtcSimulationOptions& options);
// `options.samples` tanks on `tank`'s model (give it a mesh finer than the reconstruction's).
// The same set for a seed, on any thread count.
KtcSimulatedSet simulate_ktc_tanks(const KtcTank& tank, const KtcSimulationOptions& options);

// The targets' contrasts measured on labelled tanks (KTC's training samples): the resistive and
// conductive conductivity ratios whose simulated changes, on each truth's classes moved onto the
// tank's mesh, come nearest the measured ones (least squares over every sample's difference
// frame, on a log grid of `steps` ratios each way).
struct KtcContrasts {
  double resistive = 0, conductive = 0;
  double relative_residual = 0;  // ||simulated - measured|| / ||measured|| over the changes
};
KtcContrasts fit_ktc_contrasts(const KtcTank& tank, const std::vector<Eigen::VectorXd>& changes,
                               const std::vector<ClassImage>& truths,
                               const KtcOrientation& orientation, int steps = 13);
// A labelled sample's model misfit: its change against the tank's model of its truth at the
// contrasts that fit it best alone. What a simulated tank lacks: the real tank's model error (and
// its noise, far smaller), docs/ktc.md#the-tanks-noise.
struct KtcMisfit {
  double relative = 0;  // ||model - measured|| / ||measured||, over the present values
  double rms = 0;       // V, a present value
  int values = 0;       // the change's present values
};
// A misfit above this share of the change is the truth's, not the model's: the model of the
// truth explains less than half of what was measured (KTC's sample 4: 97 %).
constexpr double kKtcMisfitExplained = 0.5;
// The noise a simulated tank's values need to stand for that error: the misfits' rms over every
// present value of the samples other than `held_out` (an index; misfits.size(): none held out)
// whose relative misfit is at most kKtcMisfitExplained. NaN where no sample is left.
double ktc_misfit_noise(const std::vector<KtcMisfit>& misfits, std::size_t held_out);

// The same fit on every sample, and on every sample but each one in turn (none for one sample):
// whether the fit, and so a model trained at its contrasts, would change with a sample held out.
// Values a change lacks (NaN) count in no misfit.
struct KtcContrastFits {
  KtcContrasts all;
  std::vector<KtcContrasts> without;  // [k]: fitted without sample k
  // The grid: each pair of ratios with its misfit on each sample (squared), and each sample's
  // measured change (squared), so that other subsets or bounds need no new simulation.
  struct Point {
    double resistive, conductive;
    std::vector<double> misfit;
  };
  std::vector<Point> grid;
  std::vector<double> measured;  // each change's squared norm over its present values
  std::vector<int> values;       // each change's present values

  // Each sample's misfit at the grid's pair that fits it best alone.
  std::vector<KtcMisfit> own_misfits() const;

  // The best pair over every sample with both ratios inside [low, high] (a band); a residual of
  // infinity when no grid pair lies inside.
  KtcContrasts best_within(double resistive_low, double resistive_high, double conductive_low,
                           double conductive_high) const;
};
KtcContrastFits fit_ktc_contrasts_held_out(const KtcTank& tank,
                                           const std::vector<Eigen::VectorXd>& changes,
                                           const std::vector<ClassImage>& truths,
                                           const KtcOrientation& orientation, int steps = 13);

// Each value's noise from a frame's repeated patterns: KTC drives four patterns twice with the same
// currents (the pair 7-9 and "9 against 7"), so the two frames differ by noise and drift alone.
// Returns the standard deviation of one value (V); InputError("frame", "patterns") when no pattern
// is repeated in the same direction (a reversed one differs by the differences' offsets too).
double repeated_pattern_noise(const Eigen::VectorXd& frame, const CurrentPatterns& patterns);

}  // namespace eitbench
