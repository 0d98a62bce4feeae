// Total variation by Chambolle-Pock: the TV weight alpha from {1e-6, 3e-6, ..., 1e-3} by
// validation CC. GCV and the L-curve do not apply: asked for them, it keeps its default alpha.
#include "eitbench/solvers/total_variation.h"

#include "method_specs.h"

namespace eitbench::methods {

MethodSpec total_variation() {
  MethodSpec spec;
  spec.name = "tv";
  spec.sweep_on_subset = true;
  spec.make = [](std::shared_ptr<const LinearProblem> problem, const MethodOptions& o) {
    TotalVariationOptions t;
    if (o.choose == "fixed") t.alpha = o.lambda;
    t.choose_by_validation = o.choose == "validation";
    if (o.tolerance > 0) t.tolerance = o.tolerance;
    t.neighbours = parse_neighbours(o.neighbours);
    return std::unique_ptr<Reconstructor>(std::make_unique<TotalVariation>(std::move(problem), t));
  };
  return spec;
}

}  // namespace eitbench::methods
