#pragma once
// Gmsh keeps global state: one mesher at a time in the process, always initialised quietly and
// finalised. Every mesher holds gmsh_lock() for as long as it holds a GmshSession.
// Gmsh also sets this thread's OpenMP thread count (its General.NumThreads, 1 by default) and
// leaves it so: a session gives the caller's back, or a mesh made before training would halve
// LibTorch's threads, and with them change the learned figures.
#include <mutex>
#include <vector>

#include "eitbench/jacobian/disk_mesh.h"

namespace eitbench::detail {

std::mutex& gmsh_mutex();

struct GmshSession {
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  int openmp_threads_;  // this thread's OpenMP thread count before Gmsh set its own
};

// Element sizes of a density, for a sensor of unit size (the disk's radius).
struct SizeSet {
  double centre;    // element size at the centre
  double boundary;  // on the rim, away from electrode edges
  double edge;      // at the electrode edges, where the CEM current density is singular
};
SizeSet sizes_for(MeshDensity density);

// A Threshold field on the distance to `curves` (sampled at 200 points each) and `points`: size_min
// there, growing linearly to size_max at dist_max. Returns its tag.
int distance_threshold(const std::vector<double>& curves, const std::vector<double>& points,
                       double size_min, double size_max, double dist_max);
// The smallest of `fields` as the background size, alone deciding sizes, and the frontal-Delaunay
// mesher (the best angles in 2-D) with smoothing.
void use_size_fields(const std::vector<double>& fields);

}  // namespace eitbench::detail
