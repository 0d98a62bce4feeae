#pragma once
// Gmsh keeps global state: one mesher at a time in the process, always initialised quietly and
// finalised. Every mesher holds gmsh_lock() for as long as it holds a GmshSession.
#include <mutex>

#include "eitbench/jacobian/disk_mesh.h"

namespace eitbench::detail {

std::mutex& gmsh_mutex();

struct GmshSession {
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

// Element sizes of a density, for a sensor of unit size (the disk's radius).
struct SizeSet {
  double centre;    // element size at the centre
  double boundary;  // on the rim, away from electrode edges
  double edge;      // at the electrode edges, where the CEM current density is singular
};
SizeSet sizes_for(MeshDensity density);

}  // namespace eitbench::detail
