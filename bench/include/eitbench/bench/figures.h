#pragma once
// Figures people would rather look at than read.
#include <string>

#include "eitbench/jacobian/mesh.h"

namespace eitbench {

// The mesh's triangles, its electrodes in colour with their numbers, and the centre node, as a PNG.
void draw_mesh_png(const Mesh& mesh, const std::string& path, int pixels = 900);

}  // namespace eitbench
