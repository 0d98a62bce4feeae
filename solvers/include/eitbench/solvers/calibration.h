#pragma once
// Calibrating the forward model to a sensor: the background conductivity and every electrode's
// contact impedance fitted, with Ceres, to a frame of the untouched sensor (absolute voltages).
// The fit runs on log sigma_0 and log z_e, so both stay positive, and on relative residuals
// (model - reference) / ||reference||; derivatives by central differences (one FEM solve each).
#include <Eigen/Core>
#include <string>

#include "eitbench/jacobian/forward_model.h"

namespace eitbench {

struct CalibrationOptions {
  int max_iterations = 50;  // Levenberg-Marquardt steps, at least 1
  // Each value may move at most this factor from its start, either way (> 1).
  double max_factor = 100;

  // Throws InputError("CalibrationOptions", field) for a value out of range.
  void validate() const;
};

struct Calibration {
  double background = 0;               // sigma_0, S/m
  Eigen::VectorXd contact_impedances;  // z_e, one an electrode (Ohm m)
  double relative_residual = 0;        // ||model - reference|| / ||reference|| at the fit
  int iterations = 0;
  bool converged = false;
};

// Fits to `reference`, the empty sensor's frame: L(L-3) absolute voltages in `order`, or an L x L
// adjacent map (ForwardModel::adjacent_map; `order` unused), which also reads the pairs that touch
// a driven electrode. Only the map determines the contact impedances well: the L(L-3) pairs carry
// no current, so the impedances move them by a fraction of the noise at 50 dB. The start is
// `background` and `forward`'s impedances (contact_impedance for every electrode, or
// contact_impedances); its current is kept. InputError naming `source` for a frame of the wrong
// length or with a value that is not finite.
Calibration calibrate(const Mesh& mesh, const ForwardOptions& forward, double background,
                      const Eigen::VectorXd& reference, MeasurementOrder order,
                      const CalibrationOptions& options = {},
                      const std::string& source = "reference");

// The same fit to every value the protocol reads (ForwardModel::measured on forward.protocol; the
// adjacent one when null): for any protocol, current patterns included, whose values on driven
// electrodes pin the contact impedances down. NaN values are missing and left out. InputError
// naming `source` for a frame of another length or with no finite value.
Calibration calibrate_measured(const Mesh& mesh, const ForwardOptions& forward, double background,
                               const Eigen::VectorXd& reference,
                               const CalibrationOptions& options = {},
                               const std::string& source = "reference");

}  // namespace eitbench
