#include "gmsh_session.h"

#include <gmsh.h>

#include <stdexcept>

namespace eitbench::detail {

std::mutex& gmsh_mutex() {
  static std::mutex m;
  return m;
}

GmshSession::GmshSession() {
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 0);
}

GmshSession::~GmshSession() {
  gmsh::finalize();
}

SizeSet sizes_for(MeshDensity density) {
  switch (density) {
    case MeshDensity::coarse:
      return {0.4, 0.2, 0.085};
    case MeshDensity::medium:
      return {0.095, 0.05, 0.018};
    case MeshDensity::fine:
      return {0.036, 0.019, 0.0065};
  }
  throw std::logic_error("unknown mesh density");
}

}  // namespace eitbench::detail
