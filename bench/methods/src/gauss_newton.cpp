// Regularised Gauss-Newton on the nonlinear forward model: lambda from {1e-5, 1e-4, ..., 1e-1} by
// validation CC.
#include "eitbench/solvers/gauss_newton.h"

#include "method_specs.h"

namespace eitbench::methods {

MethodSpec gauss_newton() {
  MethodSpec spec;
  spec.name = "gn";
  spec.sweep_on_subset = true;
  spec.make = [](std::shared_ptr<const LinearProblem> problem, const MethodOptions& o) {
    GaussNewtonOptions g;
    if (o.choose == "fixed") g.lambda = o.lambda;
    g.choose_by_validation = o.choose == "validation";
    g.absolute = o.absolute;
    if (o.tolerance > 0) g.tolerance = o.tolerance;
    auto gn = std::make_unique<GaussNewton>(std::move(problem), g);
    if (o.choose == "fixed") gn->set_lambda(o.lambda, "fixed");
    return std::unique_ptr<Reconstructor>(std::move(gn));
  };
  return spec;
}

}  // namespace eitbench::methods
