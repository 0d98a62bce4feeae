#pragma once
// A calibrated sensor as JSON (`eitbench calibrate` writes it; forward, jacobian, reconstruct and
// run take it with --sensor): the background conductivity, each electrode's contact impedance
// and the drive current, with how the calibration went.
//   {"format": "eitbench-sensor-1", "electrodes": 16, "background": 0.05,
//    "contact_impedances": [...16 values...], "current": 1,
//    "calibration": {"reference": "...", "relative_residual": ..., "iterations": ..., ...}}
#include <Eigen/Core>
#include <string>

namespace eitbench {

struct SensorFile {
  int electrodes = 0;
  double background = 0;               // S/m, positive
  Eigen::VectorXd contact_impedances;  // one an electrode, each positive
  double current = 1;                  // A, non-zero
  std::string reference;               // the frame it was calibrated on
  double relative_residual = 0;
  int iterations = 0;
  bool converged = false;
};

// Atomic. InputError naming the path when it cannot be written.
void write_sensor_file(const std::string& path, const SensorFile& sensor);
// InputError naming the path and the field for a missing, mistyped or out-of-range field (at most
// 256 electrodes, one impedance each) or a file that is not JSON.
SensorFile read_sensor_file(const std::string& path);

}  // namespace eitbench
