#pragma once
// Why an iterative solver stopped, as every report of one says it (Ceres's termination type): a
// caller can tell a converged image from one the iteration budget cut short without reading logs.
namespace eitbench {

enum class Termination {
  converged,        // the solver's own tolerance was met
  no_descent,       // no step along the search direction decreased the objective enough
  iteration_limit,  // max_iterations steps without meeting the tolerance
};
const char* to_string(Termination t);

}  // namespace eitbench
