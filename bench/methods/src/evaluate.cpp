#include "eitbench/bench/methods/evaluate.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "eitbench/bench/support/timing.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

namespace {

std::string value_range(const SampleMatrix& frames, Eigen::Index row) {
  return fmt::format("its values run from {:.3g} to {:.3g}", frames.row(row).minCoeff(),
                     frames.row(row).maxCoeff());
}

// No image that is not finite leaves a method: the frame it came from is named.
void check_images(const Reconstructor& method, const SampleMatrix& images,
                  const SampleMatrix& frames, const std::string& source) {
  for (Eigen::Index i = 0; i < images.rows(); ++i)
    if (!images.row(i).allFinite())
      throw InputError(
          source, "frame " + std::to_string(i),
          "the " + method.name() + " image is not finite (" + value_range(frames, i) + ")");
}

}  // namespace

void check_frames(const SampleMatrix& frames, const std::string& source) {
  for (Eigen::Index i = 0; i < frames.rows(); ++i)
    if (!std::isfinite(frames.row(i).squaredNorm()))
      throw InputError(source, "frame " + std::to_string(i),
                       "is not finite, or so large that its sum of squares overflows (" +
                           value_range(frames, i) + "): are the units right?");
}

Evaluation evaluate(const Reconstructor& method, const SampleMatrix& frames,
                    const SampleMatrix& labels, const PixelGrid& grid,
                    const EvaluationOptions& options) {
  check_frames(frames, options.source);
  Evaluation e;
  if (method.finds_circles())
    e.circles = method.touches_all(frames, e.images);
  else
    e.images = method.reconstruct_all(frames);
  check_images(method, e.images, frames, options.source);
  const int count = static_cast<int>(frames.rows());
  const int timed = options.timed_frames < 0 ? count : std::min(options.timed_frames, count);
  for (int i = 0; i < std::min(timed, options.warmup_calls); ++i)
    method.reconstruct(frames.row(i).transpose());
  std::vector<double> ms;
  for (int i = 0; i < timed; ++i) {
    const Eigen::VectorXd frame = frames.row(i).transpose();
    const auto t0 = std::chrono::steady_clock::now();
    const Eigen::VectorXd image = method.reconstruct(frame);
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    if (!image.allFinite())
      throw InputError(
          options.source, "frame " + std::to_string(i),
          "the " + method.name() + " image is not finite (" + value_range(frames, i) + ")");
  }
  e.latency_median_ms = percentile(ms, 0.5);
  e.latency_p95_ms = percentile(ms, 0.95);
  if (labels.rows() == frames.rows() && labels.cols() > 0)
    e.scores = score_images(e.images, labels, grid, &e.each);
  e.settings = method.settings();
  return e;
}

}  // namespace eitbench
