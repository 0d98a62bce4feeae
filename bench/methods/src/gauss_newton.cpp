// Regularised Gauss-Newton on the nonlinear forward model: lambda fixed, or from
// GaussNewtonOptions::candidates by validation CC.
#include "eitbench/solvers/gauss_newton.h"

#include "method_specs.h"

namespace eitbench::methods {

MethodSpec gauss_newton() {
  MethodSpec spec;
  spec.name = "gn";
  spec.pixel_image = true;
  spec.sweep_on_subset = true;
  spec.make = [](std::shared_ptr<const LinearProblem> problem, const MethodOptions& o) {
    GaussNewtonOptions g;
    g.choice = parse_criterion(o.choose);
    const bool given = g.choice == Criterion::fixed && o.lambda > 0;
    if (given) g.lambda = o.lambda;
    g.absolute = o.absolute;
    if (o.tolerance > 0) g.tolerance = o.tolerance;
    auto gn = std::make_unique<GaussNewton>(std::move(problem), g);
    if (given) gn->set_lambda(o.lambda, "fixed");
    return std::unique_ptr<Reconstructor>(std::move(gn));
  };
  return spec;
}

}  // namespace eitbench::methods
