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
// A build without Gmsh reads the mesh instead, from $EITBENCH_MESH_DIR/disk_mesh_file_name(options)
// as `eitbench mesh --cache DIR` wrote it on a build with Gmsh (InputError when it is missing).
Mesh generate_disk_mesh(const DiskMeshOptions& options);

// Whether this build meshes with Gmsh (true) or reads meshes from $EITBENCH_MESH_DIR (false).
bool can_generate_disk_mesh();
// The file a mesh of these options is kept under: disk-L16-medium-R1-c0.5-s1.msh, its numbers
// exact. Validates the options first.
std::string disk_mesh_file_name(const DiskMeshOptions& options);
// dir/disk_mesh_file_name(options), read; InputError naming the file when it is missing or does
// not have the options' electrodes.
Mesh read_disk_mesh(const std::string& dir, const DiskMeshOptions& options);

}  // namespace eitbench
