#pragma once
// A calibrated sensor as JSON (`eitbench calibrate` writes it; forward, jacobian, reconstruct and
// run take it with --sensor): the background conductivity, each electrode's contact impedance
// and the drive current, with how the calibration went.
//   {"format": "eitbench-sensor-1", "electrodes": 16, "background": 0.05,
//    "contact_impedances": [...16 values...], "current": 1,
//    "calibration": {"reference": "...", "relative_residual": ..., "iterations": ..., ...},
//    "press_fit": {"presses": "...", "rotate_degrees": ..., "mirror": false, "scale": ...,
//                  "touch_radius": ..., "contrast": ..., "per_depth": true, ...},
//    "noise": {"frames": "...", "references": 500, "noise": ..., "drift": ..., "signal": ...,
//              "snr_db": ..., "inputs": [...], "gains": [...], "gain_spread": ...}}
// The press fit is optional (calibrate --presses --out writes it): how a press set's recorded
// positions lie on the electrodes and the touch that explains its changes (press_sensor.h). So is
// the noise (calibrate --noise --out): what unlabelled frames say about the real frames
// (eitbench/bench/data/sensor_noise.h measures it).
#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <string>

namespace eitbench {

struct SensorPressFit {
  std::string presses;       // the press set it was fitted to
  std::string presses_hash;  // its bytes' (content_hash.h): a run refuses to score that set
  // A recorded position p lies at R(rotate_degrees) M (scale p) on the model (M: y -> -y when
  // mirror).
  double rotate_degrees = 0;
  bool mirror = false;
  double scale = 1;
  double touch_radius = 0;  // the disc's radius, the mesh's unit
  double contrast = 0;      // on the label scale, per unit of depth when per_depth
  bool per_depth = false;
  double gain = 1;  // the set's frames times this are in the model's units (its reference's fit)
  double start_residual = 0, relative_residual = 0;
  int iterations = 0;
  bool converged = false;
};

// The sensor's noise, drift, channel gains and signal size, measured on a recording's frames
// without positions. Levels are relative to the RMS of the recording's mean reference, so that
// they hold in whatever units its frames are brought to.
struct SensorNoise {
  std::string frames;  // the set it was measured on, and which of its frames ("0:500")
  int references = 0;  // repeated reference frames used
  // Per input (the protocol's difference values), the RMS of a difference frame's noise. Each
  // input's level is robust: 1.4826 x the median absolute deviation of consecutive references'
  // differences, so that a glitch or a press caught in a reference does not set it.
  double noise = 0;
  // Each input's own level (the same robust measure, relative to the same RMS; `noise` is their
  // RMS), at least a tenth of the median input's (a quantised input is not noiseless): what
  // weighs a value by its noise in the data term (reconstruct --noise-weights). Empty in files
  // written before it was measured.
  Eigen::VectorXd inputs;
  double drift = 0;   // RMS over channels of the references' slow wander beyond the noise
  double signal = 0;  // median over the frames of a difference frame's RMS
  // 20 log10(signal / noise): the simulations' convention (noise.h).
  double snr_db() const { return 20 * std::log10(signal / noise); }
  // Per channel: the mean reference, brought to the model's units by their least-squares scale,
  // over the model's reference (1 everywhere on a perfect model), or empty; and their RMS
  // deviation from 1 over the channels the model does not put near zero (|v| above a tenth of
  // its RMS), where a ratio means something.
  Eigen::VectorXd gains;
  double gain_spread = 0;
};

struct SensorFile {
  int electrodes = 0;
  double background = 0;               // S/m, positive
  Eigen::VectorXd contact_impedances;  // one an electrode, each positive
  double current = 1;                  // A, non-zero
  std::string reference;               // the frame it was calibrated on
  double relative_residual = 0;
  int iterations = 0;
  bool converged = false;
  bool fitted = true;  // false: background and impedances are nominal, not fitted to a frame
  std::optional<SensorPressFit> press_fit;
  std::optional<SensorNoise> noise;
};

// Atomic. InputError naming the path when it cannot be written.
void write_sensor_file(const std::string& path, const SensorFile& sensor);
// InputError naming the path and the field for a missing, mistyped or out-of-range field (at most
// 256 electrodes, one impedance each) or a file that is not JSON.
SensorFile read_sensor_file(const std::string& path);
// read_sensor_file, refused unless it calibrates `electrodes` electrodes: InputError naming the
// path and "electrodes", its message ending in `whose` ("the mesh has", "the data have") and the
// count.
SensorFile read_sensor_file(const std::string& path, int electrodes, const std::string& whose);

struct ForwardOptions;
// A sensor fitted to a frame gives the forward model its contact impedances and current; true
// then. A file of a press or noise fit alone (fitted false) holds nominal values, and the caller's
// stay: false.
bool apply_fitted_sensor(const SensorFile& sensor, ForwardOptions& forward);

}  // namespace eitbench
