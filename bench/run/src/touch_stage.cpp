// Touch metrics in the run: each method's blob threshold chosen on validation frames it
// reconstructs (never the test split), its test images scored with it.
#include <algorithm>
#include <cmath>

#include "eitbench/bench/methods/touch_metrics.h"
#include "eitbench/bench/methods/touch_signal.h"
#include "stages.h"

namespace eitbench::run {

bool scores_touches(const RunData& data) {
  return data.labelled && !data.test.circles.empty() && !data.validation.circles.empty();
}

namespace {

TouchFrames test_truth(const RunData& data, const Reconstruction& reconstruction) {
  const TouchFrames truth = touches_of(data.test.circles, data.data.background);
  if (reconstruction.test_touches.signals.empty()) return truth;
  return with_signals(truth, reconstruction.test_touches.signals);
}

// The median of the model's misfits at the true circles, NaN when unknown.
double median_model_error(const Reconstruction& reconstruction) {
  std::vector<double> e;
  for (double v : reconstruction.test_touches.model_error)
    if (std::isfinite(v)) e.push_back(v);
  if (e.empty()) return NAN;
  std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
  return e[e.size() / 2];
}

TouchScores with_model_error(TouchScores t, const Reconstruction& reconstruction) {
  if (!t.by_signal.empty()) t.model_error_median = median_model_error(reconstruction);
  return t;
}

}  // namespace

TouchScores touch_scores(const Context& context, const RunData& data,
                         const Reconstruction& reconstruction, const Reconstructor& method,
                         const SampleMatrix& validation_frames, const SampleMatrix& test_images) {
  if (!scores_touches(data)) return {};
  const Eigen::Index n =
      std::min<Eigen::Index>(context.config.touch_validation_frames, validation_frames.rows());
  const SampleMatrix validation_images = method.reconstruct_all(validation_frames.topRows(n));
  const std::vector<std::vector<Circle>> validation_circles(data.validation.circles.begin(),
                                                            data.validation.circles.begin() + n);
  return with_model_error(
      score_touch_images(validation_images, touches_of(validation_circles, data.source.background),
                         test_images, test_truth(data, reconstruction), reconstruction.grid),
      reconstruction);
}

TouchScores circle_touch_scores(const RunData& data, const Reconstruction& reconstruction,
                                const std::vector<std::vector<Circle>>& test_circles) {
  if (!scores_touches(data)) return {};
  const double background = data.data.background;
  return with_model_error(
      score_touches(touches_of(test_circles, background), test_truth(data, reconstruction),
                    reconstruction.grid.radius()),
      reconstruction);
}

}  // namespace eitbench::run
