// Gmsh .msh (2.2 and 4.1, ASCII) through read_msh.
#include <sstream>

#include "eitbench/jacobian/msh_io.h"
#include "fuzz_target.h"

EITBENCH_FUZZ_TARGET({
  std::istringstream in(bytes);
  eitbench::read_msh(in, "fuzz.msh");
})
