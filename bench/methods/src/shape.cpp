// The shape fit (K circles by Ceres): `shape` re-solves the FEM at every step, `shape-linear`
// uses the Jacobian at the background. Both choose K by BIC; the benchmark chooses the BIC's
// penalty weight from ShapeOptions::candidates by validation CC.
#include "eitbench/solvers/shape.h"

#include "method_specs.h"

namespace eitbench::methods {
namespace {

MethodSpec shape_spec(const std::string& name, ShapeForward forward) {
  MethodSpec spec;
  spec.name = name;
  spec.sweep_on_subset = true;
  spec.make = [forward](std::shared_ptr<const LinearProblem> problem, const MethodOptions& o) {
    ShapeOptions s;
    s.forward = forward;
    s.choice = parse_criterion(o.choose);
    const bool given = s.choice == Criterion::fixed && o.lambda > 0;
    if (given) s.penalty = o.lambda;  // --lambda: the BIC's penalty weight
    s.robust_scale = o.robust;
    return std::unique_ptr<Reconstructor>(
        std::make_unique<ShapeReconstructor>(std::move(problem), s));
  };
  return spec;
}

}  // namespace

MethodSpec shape() {
  return shape_spec("shape", ShapeForward::full);
}
MethodSpec shape_linear() {
  return shape_spec("shape-linear", ShapeForward::linear);
}

}  // namespace eitbench::methods
