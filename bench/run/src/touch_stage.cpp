// Touch metrics in the run: each method's blob threshold chosen on validation frames it
// reconstructs (never the test split), its test images scored with it.
#include <algorithm>

#include "eitbench/bench/methods/touch_metrics.h"
#include "stages.h"

namespace eitbench::run {

bool scores_touches(const RunData& data) {
  return data.labelled && !data.test.circles.empty() && !data.validation.circles.empty();
}

TouchScores touch_scores(const Context& context, const RunData& data,
                         const Reconstruction& reconstruction, const Reconstructor& method,
                         const SampleMatrix& validation_frames, const SampleMatrix& test_images) {
  if (!scores_touches(data)) return {};
  const Eigen::Index n =
      std::min<Eigen::Index>(context.config.touch_validation_frames, validation_frames.rows());
  const SampleMatrix validation_images = method.reconstruct_all(validation_frames.topRows(n));
  const std::vector<std::vector<Circle>> validation_circles(data.validation.circles.begin(),
                                                            data.validation.circles.begin() + n);
  return score_touch_images(
      validation_images, touches_of(validation_circles, data.source.background), test_images,
      touches_of(data.test.circles, data.data.background), reconstruction.grid);
}

TouchScores circle_touch_scores(const RunData& data, const Reconstruction& reconstruction,
                                const std::vector<std::vector<Circle>>& test_circles) {
  if (!scores_touches(data)) return {};
  const double background = data.data.background;
  return score_touches(touches_of(test_circles, background),
                       touches_of(data.test.circles, background), reconstruction.grid.radius());
}

}  // namespace eitbench::run
