#pragma once
// Frames measured by real instruments, from the files they and their users write: CSV, NumPy
// .npy / .npz, MATLAB .mat (level 5, compressed or not; v7.3 through HDF5).
//
// A frame is recognised by its length: L(L-3) values in --order (rotating or ascending), the
// L(L-3)/2 reduced values (completed by reciprocity), or L^2 values of the full L x L map, (d, m)
// at d L + m, with the unmeasured entries present and ignored. A 2-D array holds one frame a row,
// or one a column when only its row count is a frame length (MATLAB files, where EIDORS stores one
// frame a column, prefer columns when both fit). With another protocol (ImportOptions::protocol), a
// frame is its C channels in the protocol's order.
#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <string>

#include "eitbench/bench/data/dataset.h"
#include "eitbench/jacobian/protocol.h"
#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench {

struct ImportOptions {
  int electrodes = 16;
  MeasurementOrder order = MeasurementOrder::rotating;  // of L(L-3)-value frames
  std::string variable;  // array (.npz) or variable (.mat); default: the only numeric one, else
                         // the first of frames, data, vv, v, voltages, meas
  // Keep L x L maps whole in Measurements::maps (calibration reads the pairs that touch a driven
  // electrode); off by default, as the frames need only their L(L-3) pairs.
  bool keep_maps = false;
  // The protocol the frames were measured on (docs/protocols.md); null: the adjacent one, whose
  // frames come in the layouts above. Any other takes frames of its channels in its order.
  std::shared_ptr<const MeasurementProtocol> protocol;
  // One reference frame per frame (boards that record one before every press): frame i minus
  // reference i; otherwise frame i minus the references' mean.
  bool paired_reference = false;
  // Differences relative to each frame's own reference, (v - v_ref) / v_ref, times the mean
  // reference (so they stay in voltage units, which every method and the group's signs assume):
  // the same as v - v_ref with one reference; with paired ones each reference's gain divides out.
  bool relative = false;
};

struct Measurements {
  SampleMatrix frames;      // N x L(L-3), rotating order; N x C for another protocol
  SampleMatrix maps;        // N x L*L, v(d, m) at d * L + m: L x L input with keep_maps, else empty
  std::string description;  // format, variable and layout, for people
  bool reduced_input = false;
  double reciprocity_error =
      0;  // mean relative error of the frames as measured (0 for reduced input)
};

// InputError names the file and the variable or field.
Measurements read_measurements(const std::string& path, const ImportOptions& options);

// Frames and a reference (empty-sensor) file as a data set without labels: differences are
// frame - reference (the reference file's mean frame when it holds several). Without a reference
// the frames are taken to be differences already, and the reference is zero.
Dataset import_measurements(const std::string& path, const std::string& reference_path,
                            const ImportOptions& options,
                            const std::string& reference_variable = "");
// The same for frames already read (read_measurements), so that callers read the file once.
Dataset import_measurements(const Measurements& frames, const std::string& reference_path,
                            const ImportOptions& options,
                            const std::string& reference_variable = "");

// The frames whose difference from the reference is zero everywhere (a frame equal to the
// reference, or a copy of it): worth a warning, as every method draws them as no touch.
int frames_without_change(const Dataset& data);

// Measured frames in a model's units. A measured frame is in the instrument's units (its current,
// its gain, volts or millivolts); a model trained or tuned on simulated frames expects the
// simulation's. The factor is the least-squares fit of the measured empty-sensor frame to the
// model's, scale = <model, measured> / <measured, measured>, and `fit` is the cosine between the
// two: near 1 when the sensor and its measurement order match the model's. A zero measured
// reference (frames imported as differences) gives scale 1 and fit NaN.
struct ReferenceCalibration {
  double scale = 1;
  double fit = NAN;
};
ReferenceCalibration calibrate_to_model(const Eigen::VectorXd& measured_reference,
                                        const Eigen::VectorXd& model_reference);

}  // namespace eitbench
