// DiskMeshOptions, and the disk meshes of builds without Gmsh: read from files that a build with
// Gmsh wrote (`eitbench mesh --cache DIR`), so that a machine without Gmsh (the GPU image) runs
// the same meshes, node for node.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "eitbench/jacobian/disk_mesh.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/msh_io.h"

namespace eitbench {

MeshDensity parse_density(const std::string& name) {
  if (name == "coarse") return MeshDensity::coarse;
  if (name == "medium") return MeshDensity::medium;
  if (name == "fine") return MeshDensity::fine;
  throw InputError("MeshDensity", "name",
                   "unknown mesh density '" + name + "' (coarse, medium or fine)");
}

std::string to_string(MeshDensity density) {
  switch (density) {
    case MeshDensity::coarse:
      return "coarse";
    case MeshDensity::medium:
      return "medium";
    case MeshDensity::fine:
      return "fine";
  }
  return "?";
}

void DiskMeshOptions::validate() const {
  auto fail = [](const char* field, const std::string& why) {
    throw InputError("DiskMeshOptions", field, why);
  };
  if (electrodes < 4 || electrodes > 256)
    fail("electrodes", "need 4 <= L <= 256, got " + std::to_string(electrodes));
  if (!(radius > 0) || !std::isfinite(radius)) fail("radius", "must be positive and finite");
  if (!(electrode_coverage > 0 && electrode_coverage < 1))
    fail("electrode_coverage", "must lie strictly between 0 and 1");
  if (!(size_factor >= 0.1 && size_factor <= 10)) fail("size_factor", "must lie in [0.1, 10]");
}

std::string disk_mesh_file_name(const DiskMeshOptions& o) {
  o.validate();
  // %.17g: the name tells two option sets apart exactly as the mesher does.
  char name[200];
  std::snprintf(name, sizeof name, "disk-L%d-%s-R%.17g-c%.17g-s%.17g.msh", o.electrodes,
                to_string(o.density).c_str(), o.radius, o.electrode_coverage, o.size_factor);
  return name;
}

bool can_generate_disk_mesh() {
#ifdef EITBENCH_HAVE_GMSH
  return true;
#else
  return false;
#endif
}

Mesh read_disk_mesh(const std::string& dir, const DiskMeshOptions& o) {
  const std::string name = disk_mesh_file_name(o), path = dir + "/" + name;
  if (!std::ifstream(path))
    throw InputError(path, "",
                     "no such mesh: `eitbench mesh --cache " + dir +
                         "` with the same mesh options writes it on a build with Gmsh");
  Mesh mesh = read_msh_file(path);
  if (mesh.num_electrodes() != o.electrodes)
    throw InputError(path, "electrodes",
                     "has " + std::to_string(mesh.num_electrodes()) + " electrodes, not " +
                         std::to_string(o.electrodes));
  return mesh;
}

#ifndef EITBENCH_HAVE_GMSH
Mesh generate_disk_mesh(const DiskMeshOptions& o) {
  const char* dir = std::getenv("EITBENCH_MESH_DIR");
  if (!dir || !*dir)
    throw InputError("EITBENCH_MESH_DIR", "",
                     "not set, and this build has no Gmsh to mesh " + disk_mesh_file_name(o) +
                         ": set it to a folder that `eitbench mesh --cache DIR` filled on a "
                         "build with Gmsh, or pass --mesh FILE");
  return read_disk_mesh(dir, o);
}
#endif

}  // namespace eitbench
