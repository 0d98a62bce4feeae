#include "eitbench/solvers/termination.h"

namespace eitbench {

const char* to_string(Termination t) {
  switch (t) {
    case Termination::converged:
      return "converged";
    case Termination::no_descent:
      return "no descent";
    case Termination::iteration_limit:
      return "iteration limit";
  }
  return "?";
}

}  // namespace eitbench
