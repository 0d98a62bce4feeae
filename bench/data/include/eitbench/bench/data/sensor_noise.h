#pragma once
// A sensor's noise, drift, channel gains and signal size, measured from a recording's frames
// without positions (calibrate --noise): what simulation and the label-free choice of a
// regulariser need to know about the real frames (docs/real-presses.md#the-sensors-noise).
//
// The references a press set records before each press (import --paired-reference) are repeated
// frames of the untouched sensor. Between two consecutive ones the sensor barely moves, so their
// difference is noise, and it is distributed as the noise of a difference frame (a pressed frame
// minus its own reference): two independent frames' noise. Over the whole recording the
// references also wander (temperature, the skin settling): what their spread holds beyond the
// noise is the drift. Every level is given relative to the RMS of the mean reference, so that it
// holds in any units the frames are later brought to.
#include <cstdint>
#include <string>

#include "eitbench/bench/data/dataset.h"
#include "eitbench/bench/io/sensor_file.h"  // SensorNoise

namespace eitbench {

// From `set`'s frames first..last-1 (its paired references and its differences). Throws
// InputError(path, "references") when the set has no paired references, fewer than 3 in the
// range, a zero mean reference, or references too equal to show any noise. `model_reference` (the
// model's frame of the untouched sensor, the protocol's channels) may be empty: no gains.
SensorNoise measure_sensor_noise(const Dataset& set, const std::string& path, int first, int last,
                                 const Eigen::VectorXd& model_reference);

// The noise's RMS per input in the units of frames whose mean reference is `reference` (those
// units, whatever scale they were brought to).
double noise_in_units_of(const SensorNoise& noise, const Eigen::VectorXd& reference);

// Difference frames of the model (the protocol's inputs, in the units of `model_reference`) as
// the sensor would give them: each value times its channel's measured gain (a channel without a
// gain, or gains of another length, keeps 1), plus white Gaussian noise of the measured level.
// Row i draws from RandomStream(seed, i): the same for any thread count or subset of rows.
void apply_sensor_noise(SampleMatrix& differences, const SensorNoise& noise,
                        const Eigen::VectorXd& model_reference, std::uint64_t seed);

}  // namespace eitbench
