// One-step linear reconstruction, x = P A^T (A P A^T + lambda I)^-1 y with P = (R^T R)^-1, with
// four priors.
#include "eitbench/solvers/tikhonov.h"

#include "method_specs.h"

namespace eitbench::methods {
namespace {

// The four share TikhonovOptions' lambda grid (41 values, trace(A P A^T)/m x 10^[-8, 2]), chosen
// by GCV, the L-curve, the discrepancy principle or validation CC: identity prior, NOSER (R^T R =
// diag(A^T A)^0.5), the Laplacian on pixels or elements, and the smooth (Gaussian covariance)
// prior.
MethodSpec tikhonov_with(const std::string& prior) {
  MethodSpec spec;
  spec.name = prior;
  spec.default_choice = "gcv";
  spec.pixel_image = true;
  spec.one_step = true;
  spec.make = [prior](std::shared_ptr<const LinearProblem> problem, const MethodOptions& o) {
    TikhonovOptions t;
    t.prior = parse_prior(prior);
    t.choice = parse_criterion(o.choose);
    if (t.choice == Criterion::fixed) t.lambda = o.lambda;
    if (t.choice == Criterion::discrepancy) t.noise = o.noise;
    t.discrepancy_factor = o.discrepancy_factor;
    t.relative = o.relative_lambda;
    t.neighbours = parse_neighbours(o.neighbours);
    t.noser_exponent = o.noser_exponent;
    t.smooth_length = o.smooth_length;
    return std::unique_ptr<Reconstructor>(std::make_unique<Tikhonov>(std::move(problem), t));
  };
  return spec;
}

}  // namespace

MethodSpec tikhonov() {
  return tikhonov_with("tikhonov");
}
MethodSpec noser() {
  return tikhonov_with("noser");
}
MethodSpec laplace() {
  return tikhonov_with("laplace");
}
MethodSpec smooth() {
  return tikhonov_with("smooth");
}

}  // namespace eitbench::methods
