// GREIT: a linear map trained on small targets; its lambda from {1e-5, 1e-4, ..., 1} by validation
// CC.
#include "eitbench/solvers/greit.h"

#include "method_specs.h"

namespace eitbench::methods {

MethodSpec greit() {
  MethodSpec spec;
  spec.name = "greit";
  spec.make = [](std::shared_ptr<const LinearProblem> problem, const MethodOptions& o) {
    GreitOptions g;
    if (o.choose == "fixed") g.lambda = o.lambda;
    g.choose_by_validation = o.choose == "validation";
    return std::unique_ptr<Reconstructor>(std::make_unique<Greit>(std::move(problem), g));
  };
  return spec;
}

}  // namespace eitbench::methods
