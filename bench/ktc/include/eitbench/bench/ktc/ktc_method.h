#pragma once
// A reconstruction method on KTC's tank (docs/ktc.md#methods): every model-based method of the
// registry built on the calibrated tank's linear problem, reading each frame's present values
// (MissingValues: a level's removed electrodes leave their rows out), the data term weighted by
// KTC's noise model, the image resampled onto KTC's grid and segmented.
#include <memory>
#include <string>
#include <vector>

#include "eitbench/bench/ktc/segmentation.h"
#include "eitbench/bench/ktc/tank.h"
#include "eitbench/solvers/missing_values.h"

namespace eitbench {

// The data term's noise: each value's standard deviation is
// sqrt((relative |u_ref|)^2 + (floor max |u_ref|)^2) on the empty tank's frame u_ref, the model
// the challenge's baseline used (0.05 % of the value and 0.01 % of the largest).
struct KtcNoise {
  double relative = 5e-4;
  double floor = 1e-4;

  // Whether the two make a noise model: both non-negative and finite, not both zero. Every place
  // that takes a share from outside (--noise-sweep, a run's settings) asks this.
  bool valid() const;
  // InputError("KtcNoise", field) naming the field where !valid().
  void validate() const;
  Eigen::VectorXd of(const Eigen::VectorXd& reference) const;
};

struct KtcSetup {
  KtcTank tank;
  PixelGrid grid{64, 0.115};                     // the images' grid: the tank's disk
  std::shared_ptr<const LinearProblem> problem;  // every value, weight 1, at the calibration
  Eigen::VectorXd noise;                         // one standard deviation a value
  KtcOrientation orientation;
};

// The linear problem on the calibrated tank. grid_size pixels a side (check_ktc_grid).
KtcSetup make_ktc_setup(KtcTank tank, int grid_size = 64, const KtcNoise& noise = {},
                        const KtcOrientation& orientation = {});
// InputError("KtcSetup", "grid") unless 16 <= grid_size <= 256.
void check_ktc_grid(int grid_size);

// The methods a KTC run ranks (every model-based one but the shape fits), and each one's
// candidate regularisation weights on its relative scale (Reconstructor::set_regularisation).
const std::vector<std::string>& ktc_method_names();
const std::vector<double>& ktc_candidates(const std::string& method);

// The setting `eitbench ktc` applies without a run: what `eitbench run --ktc` tuned on the
// challenge's four training samples with the default tank, grid and noise (docs/ktc.md).
struct KtcSetting {
  double lambda = 0;
  SegmentationRule rule;
  double noise_relative = KtcNoise().relative;  // the data term's noise model (with its floor)
};
KtcSetting ktc_default_setting(const std::string& method);

// `method` for KTC's frames, its regularisation fixed at `relative` (positive, finite).
// InputError naming --method for a method that is not a KTC one, --lambda for a bad weight.
// The method is not safe to use from several threads while set_regularisation changes it.
std::unique_ptr<MissingValues> make_ktc_method(const KtcSetup& setup, const std::string& method,
                                               double relative);

// The difference frame of a measurement at `level`: Uel - Uelref, NaN where the level removes.
Eigen::VectorXd ktc_difference(const KtcMeasurement& measurement, const KtcSetup& setup, int level);

// A reconstruction on KTC's grid, and its classes.
Eigen::MatrixXd ktc_image(const KtcSetup& setup, const Eigen::VectorXd& image);

}  // namespace eitbench
