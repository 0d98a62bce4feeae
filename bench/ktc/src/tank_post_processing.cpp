#include "eitbench/bench/ktc/tank_post_processing.h"

#include <algorithm>
#include <cmath>

#include "eitbench/bench/methods/registry.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

void KtcOneStep::validate() const {
  // The methods that reconstruct a frame by one linear map (a solve per frame would make the
  // training set's images hours of work).
  const std::vector<std::string> one_step = method_names_with(&MethodSpec::one_step);
  if (std::find(one_step.begin(), one_step.end(), method) == one_step.end())
    throw InputError("KtcOneStep", "method",
                     "'" + method + "' is not a one-step method (" +
                         joined_method_names_with(&MethodSpec::one_step) + ")");
  if (!(lambda > 0) || !std::isfinite(lambda))
    throw InputError("KtcOneStep", "lambda", "must be positive and finite");
}

std::unique_ptr<MissingValues> make_ktc_one_step(const KtcSetup& setup, const KtcOneStep& step) {
  step.validate();
  return make_ktc_method(setup, step.method, step.lambda);
}

SampleMatrix ktc_one_step_inputs(const MissingValues& one_step, const PixelGrid& grid,
                                 const SampleMatrix& frames) {
  const SampleMatrix images = one_step.reconstruct_all(frames);
  if (images.cols() != grid.num_pixels())
    throw std::invalid_argument("ktc_one_step_inputs: the method's images are not on the grid");
  SampleMatrix inputs(images.rows(), grid.num_inside());
  Eigen::Index c = 0;
  for (Eigen::Index p = 0; p < images.cols(); ++p)
    if (grid.mask()[p]) inputs.col(c++) = images.col(p);
  return inputs;
}

LabelledFrames ktc_post_frames(const KtcSimulatedSet& tanks, const CurrentPatterns& patterns,
                               bool group, std::uint64_t seed, const MissingValues& one_step,
                               const PixelGrid& grid) {
  LabelledFrames out = ktc_level_frames(tanks, patterns, group, seed);
  out.frames = ktc_one_step_inputs(one_step, grid, out.frames);
  return out;
}

AugmentSetup ktc_post_setup(const CurrentPatterns& patterns, int grid, int inputs) {
  AugmentSetup setup = ktc_network_setup(patterns, grid);
  setup.image_inputs = inputs;
  return setup;
}

ClassImage ktc_post_classes(const LearnedModel& model, const MissingValues& one_step,
                            const PixelGrid& grid, const Eigen::VectorXd& change,
                            double threshold) {
  const SampleMatrix inputs = ktc_one_step_inputs(one_step, grid, change.transpose());
  if (inputs.cols() != model.info().image_inputs)
    throw InputError("model", "image_inputs",
                     "reads " + std::to_string(model.info().image_inputs) +
                         " pixels of the one-step image, the grid has " +
                         std::to_string(inputs.cols()) + " inside the tank");
  return ktc_output_classes(model.reconstruct(inputs).row(0).transpose(), threshold);
}

}  // namespace eitbench
