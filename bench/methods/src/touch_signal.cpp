#include "eitbench/bench/methods/touch_signal.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "eitbench/jacobian/error.h"

namespace eitbench {

TouchVisibility touch_visibility(const ForwardModel& model,
                                 const std::vector<std::vector<Circle>>& circles,
                                 const SampleMatrix& frames, double background) {
  if (!(background > 0 && std::isfinite(background)))
    throw InputError("touch_visibility", "background", "must be positive and finite");
  if (frames.rows() != static_cast<Eigen::Index>(circles.size()) ||
      frames.cols() != model.measurement_protocol().input_size())
    throw InputError("touch_visibility", "frames",
                     "must hold one frame of the model's inputs for each list of circles");
  const Mesh& mesh = model.mesh();
  auto inputs = [&](const std::vector<Circle>& touches) {
    return model.inputs(model.solve(conductivity_from_circles(mesh, touches, background)));
  };
  const Eigen::VectorXd none = inputs({});
  TouchVisibility out;
  out.signals.resize(circles.size());
  out.model_error.assign(circles.size(), NAN);
  tbb::parallel_for(std::size_t{0}, circles.size(), [&](std::size_t i) {
    const std::vector<Circle>& all = circles[i];
    const Eigen::VectorXd with_all = inputs(all);
    const Eigen::Index row = static_cast<Eigen::Index>(i);
    const double size = frames.row(row).norm();
    if (size > 0)
      out.model_error[i] = (with_all - none - frames.row(row).transpose()).norm() / size;
    const double change = (with_all - none).norm();
    for (std::size_t j = 0; j < all.size(); ++j) {
      std::vector<Circle> others = all;
      others.erase(others.begin() + static_cast<std::ptrdiff_t>(j));
      const Eigen::VectorXd without = others.empty() ? none : inputs(others);
      out.signals[i].push_back(change > 0 ? (with_all - without).norm() / change : 0.0);
    }
  });
  return out;
}

TouchFrames with_signals(TouchFrames truth, const std::vector<std::vector<double>>& signals) {
  if (signals.size() != truth.size())
    throw InputError("with_signals", "signals", "must hold one list a frame of the truth");
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (signals[i].size() != truth[i].size())
      throw InputError("with_signals", "signals",
                       "frame " + std::to_string(i) + " has another number of touches");
    for (std::size_t j = 0; j < truth[i].size(); ++j) truth[i][j].signal = signals[i][j];
  }
  return truth;
}

}  // namespace eitbench
