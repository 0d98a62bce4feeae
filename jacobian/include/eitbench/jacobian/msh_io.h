#pragma once
// Gmsh ASCII meshes, versions 2.2 and 4.1. Electrodes are physical groups named electrode_0 ...
// electrode_{L-1}: 1-D groups (line segments) or 0-D groups (a point electrode); the triangles are
// those of the 2-D physical groups (all triangles when the file has no 2-D physical group).
#include <iosfwd>
#include <string>

#include "eitbench/jacobian/mesh.h"

namespace eitbench {

enum class MshVersion { v22, v41 };

// Throws InputError naming `source` (the file) and the section or field that is wrong.
Mesh read_msh(std::istream& in, const std::string& source);
Mesh read_msh_file(const std::string& path);

void write_msh(std::ostream& out, const Mesh& mesh, MshVersion version);

}  // namespace eitbench
