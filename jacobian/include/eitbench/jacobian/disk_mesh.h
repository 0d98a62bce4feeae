#pragma once
// The disk sensor's mesh, with exact D_L symmetry: every rotation by 2*pi/L and the mirror about
// the axis through electrode 0 map nodes to nodes and triangles to triangles (docs/conventions.md).
#include <string>

#include "eitbench/jacobian/mesh.h"

namespace eitbench {

enum class MeshDensity { coarse, medium, fine };

// coarse | medium | fine; InputError("MeshDensity", "name") otherwise.
MeshDensity parse_density(const std::string& name);
std::string to_string(MeshDensity density);

struct DiskMeshOptions {
  int electrodes = 16;  // L, 4 <= L <= 256 (8, 16 and 32 are tested)
  MeshDensity density = MeshDensity::medium;
  double radius = 1.0;  // R, positive and finite
  // The fraction of the perimeter under electrodes, strictly between 0 and 1; each is coverage/L.
  double electrode_coverage = 0.5;
  // Mesh size scale on top of the density, in [0.1, 10]: 0.5 halves every size (about 4x the
  // triangles).
  double size_factor = 1.0;

  // Throws InputError("DiskMeshOptions", field) for a value out of range.
  void validate() const;
};

// Electrode e is the arc centred at theta_e = 2*pi*e/L of angular width 2*pi*coverage/L.
// Meshes one fundamental sector (0 <= theta <= pi/L) with Gmsh's frontal-Delaunay mesher, refined
// towards the electrode edges, and replicates it by the group's reflections. The centre is a node
// surrounded by L triangles: symmetry forces that, so for L > 24 their apex angle 360/L deg is the
// mesh's smallest angle. Validates the options first. Deterministic; safe to call from several
// threads (Gmsh's global state is behind a mutex, so calls mesh one at a time).
Mesh generate_disk_mesh(const DiskMeshOptions& options);

}  // namespace eitbench
