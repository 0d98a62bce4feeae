#include "eitbench/bench/methods/evaluate.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "eitbench/bench/support/timing.h"

namespace eitbench {

Evaluation evaluate(const Reconstructor& method, const SampleMatrix& frames,
                    const SampleMatrix& labels, const PixelGrid& grid,
                    const EvaluationOptions& options) {
  Evaluation e;
  if (method.finds_circles())
    e.circles = method.touches_all(frames, e.images);
  else
    e.images = method.reconstruct_all(frames);
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
    if (!image.allFinite()) throw std::runtime_error(method.name() + ": non-finite image");
  }
  e.latency_median_ms = percentile(ms, 0.5);
  e.latency_p95_ms = percentile(ms, 0.95);
  if (labels.rows() == frames.rows() && labels.cols() > 0)
    e.scores = score_images(e.images, labels, grid, &e.each);
  e.settings = method.settings();
  return e;
}

}  // namespace eitbench
