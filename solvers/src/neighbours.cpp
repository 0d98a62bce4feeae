#include "eitbench/solvers/neighbours.h"

#include "eitbench/jacobian/error.h"

namespace eitbench {

Neighbours parse_neighbours(const std::string& name) {
  if (name == "pixels") return Neighbours::pixels;
  if (name == "elements") return Neighbours::elements;
  throw InputError("Neighbours", "name", "unknown neighbours '" + name + "' (pixels or elements)");
}

}  // namespace eitbench
