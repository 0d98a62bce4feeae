#pragma once
// eitbench calibrate --presses (press_frame_command.cpp): the frame of a press set's recorded
// positions, and the sensor fit that --out writes.
#include <string>

#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/jacobian/mesh.h"
#include "eitbench/solvers/press_frame.h"
#include "eitbench/solvers/press_sensor.h"

namespace eitbench::cli {

// Prints the best turn and handedness of the set at `path`, and how to apply them at import.
void print_press_frame(const Mesh& mesh, const std::string& path, const PressFrameOptions& options);

// The frame search, then the sensor fit from it (press_sensor.h) on the set's changes brought to
// the model's units by its reference frame, on the model of `forward` (the sensor's impedances
// and current) at `background`; prints both.
SensorPressFit fit_press_sensor_file(const Mesh& mesh, const std::string& path,
                                     const PressFrameOptions& frame,
                                     const PressSensorOptions& options,
                                     const ForwardOptions& forward, double background);

}  // namespace eitbench::cli
