#pragma once
// The learned reconstructor's files: the model (.pt, a LibTorch archive with eitbench's metadata)
// and the training checkpoint beside it. learned/ makes and reads the bytes; these move them.
#include <string>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/jacobian/pixel_grid.h"
#include "eitbench/learned.h"

namespace eitbench {

LearnedModel read_model_file(const std::string& path);
void write_model_file(const std::string& path, const LearnedModel& model);
// Checks that a model fits a sensor: InputError naming `path` when the electrode count or the
// image size differ.
void check_model_fits(const LearnedModel& model, const std::string& path, int electrodes,
                      int image_size);
// The same, and that the model draws on `grid`'s pixels: a model trained on the disk does not fit
// a square sensor's set of the same size, nor one trained on the square the disk's.
void check_model_fits(const LearnedModel& model, const std::string& path, int electrodes,
                      const PixelGrid& grid);
// InputError(path, "protocol") when the model was trained on another protocol (channels, order
// or magnitude flag): a model of 192 inputs given 208-channel frames, or the same count in
// another order, would read them wrongly without an error.
void check_model_protocol(const LearnedModel& model, const std::string& path,
                          const MeasurementProtocol& protocol);

}  // namespace eitbench
