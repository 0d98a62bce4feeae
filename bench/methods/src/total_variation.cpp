// Total variation by Chambolle-Pock: the TV weight alpha fixed, or from
// TotalVariationOptions::candidates by validation CC. GCV and the L-curve do not apply: asked for
// them, the solver refuses.
#include "eitbench/solvers/total_variation.h"

#include "method_specs.h"

namespace eitbench::methods {

MethodSpec total_variation() {
  MethodSpec spec;
  spec.name = "tv";
  spec.pixel_image = true;
  spec.sweep_on_subset = true;
  spec.make = [](std::shared_ptr<const LinearProblem> problem, const MethodOptions& o) {
    TotalVariationOptions t;
    t.choice = parse_criterion(o.choose);
    const bool given = t.choice == Criterion::fixed && o.lambda > 0;
    if (given) t.alpha = o.lambda;
    if (o.tolerance > 0) t.tolerance = o.tolerance;
    t.neighbours = parse_neighbours(o.neighbours);
    auto tv = std::make_unique<TotalVariation>(std::move(problem), t);
    if (given) tv->set_alpha(o.lambda, "fixed");
    return std::unique_ptr<Reconstructor>(std::move(tv));
  };
  return spec;
}

}  // namespace eitbench::methods
