// GREIT: a linear map trained on small targets; its lambda fixed, or from GreitOptions::candidates
// by validation CC.
#include "eitbench/solvers/greit.h"

#include "method_specs.h"

namespace eitbench::methods {

MethodSpec greit() {
  MethodSpec spec;
  spec.name = "greit";
  spec.pixel_image = true;
  spec.one_step = true;
  spec.make = [](std::shared_ptr<const LinearProblem> problem, const MethodOptions& o) {
    GreitOptions g;
    g.choice = parse_criterion(o.choose);
    if (g.choice == Criterion::fixed && o.lambda > 0) g.lambda = o.lambda;
    return std::unique_ptr<Reconstructor>(std::make_unique<Greit>(std::move(problem), g));
  };
  return spec;
}

}  // namespace eitbench::methods
