#pragma once
// Internal: backtracking to Armijo's sufficient decrease along a (projected) search path.
#include <optional>

#include "eitbench/jacobian/error.h"

namespace eitbench::detail {

struct LineSearchOptions {
  double armijo = 1e-4;  // the fraction of the linear model's decrease a step must achieve
  int max_halvings = 20;
};

// Tries t = 1, 1/2, 1/4, ... and returns the first trial whose objective f satisfies
//   f <= f0 + armijo * slope(trial),
// where slope(trial) is the directional derivative times the step actually taken (negative for a
// descent direction; it takes the trial because a projected step is not t times the direction).
// `evaluate(t)` returns a trial with a member `phi`; a trial the numbers defeat (NumericalError:
// a conductivity so extreme that the forward system lost definiteness) is no decrease. Every other
// exception (memory, bad input, a programming error) propagates: it says nothing about the
// objective. No trial accepted: nullopt.
template <typename Evaluate, typename Slope>
auto armijo_backtracking(double f0, Evaluate&& evaluate, Slope&& slope,
                         const LineSearchOptions& options = {})
    -> std::optional<decltype(evaluate(1.0))> {
  double t = 1.0;
  for (int k = 0; k <= options.max_halvings; ++k, t *= 0.5) {
    try {
      auto trial = evaluate(t);
      if (trial.phi <= f0 + options.armijo * slope(trial)) return trial;
    } catch (const NumericalError&) {
      // no decrease at this step: try a shorter one
    }
  }
  return std::nullopt;
}

}  // namespace eitbench::detail
