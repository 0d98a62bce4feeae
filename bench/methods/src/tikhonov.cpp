// One-step linear reconstruction, x = P A^T (A P A^T + lambda R)^-1 y, with three priors.
#include "eitbench/solvers/tikhonov.h"

#include "method_specs.h"

namespace eitbench::methods {
namespace {

MethodSpec tikhonov_with(const std::string& prior, const std::string& tuning) {
  MethodSpec spec;
  spec.name = prior;
  spec.tuning = tuning;
  spec.make = [prior](std::shared_ptr<const LinearProblem> problem, const MethodOptions& o) {
    TikhonovOptions t;
    t.prior = parse_prior(prior);
    t.choice = o.choose == "fixed" ? Choice::fixed : parse_choice(o.choose);
    t.lambda = o.lambda;
    t.neighbours = parse_neighbours(o.neighbours);
    return std::unique_ptr<Reconstructor>(std::make_unique<Tikhonov>(std::move(problem), t));
  };
  return spec;
}

// The three share the lambda grid of TikhonovOptions (41 values, trace scale x 10^[-8, 2]).
constexpr const char* kGrid = "lambda from 41 log-spaced values, trace(A P A^T)/m x 10^[-8, 2]";

}  // namespace

MethodSpec tikhonov() {
  return tikhonov_with(
      "tikhonov", std::string("identity prior; ") + kGrid + ", by GCV, L-curve or validation CC");
}
MethodSpec noser() {
  return tikhonov_with("noser", std::string("NOSER prior diag(J^T J); ") + kGrid +
                                    ", by GCV, L-curve or validation CC");
}
MethodSpec laplace() {
  return tikhonov_with("laplace", std::string("Laplacian prior (pixels or elements); ") + kGrid +
                                      ", by GCV, L-curve or validation CC");
}

}  // namespace eitbench::methods
