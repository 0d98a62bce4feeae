#pragma once
// Internal: the two neighbour graphs the regularising priors share (Laplace in tikhonov.cpp, TV in
// tv_gradient.cpp) and the pixel-to-unknown map the linear problem builds P with.
#include <vector>

#include "eitbench/jacobian/mesh.h"

namespace eitbench::detail {

// For each of the grid's `num_pixels` image pixels, its unknown j (pixels[j] == pixel), or -1 for
// a pixel outside the disk.
std::vector<int> unknown_of_pixel(const std::vector<int>& pixels, int num_pixels);

// A mesh edge shared by two triangles: `first` is the triangle seen first on it, in the order of
// the triangles and their edges; (a, b) its nodes.
struct InteriorEdge {
  int first, second, a, b;
};
std::vector<InteriorEdge> interior_edges(const Mesh& mesh);

}  // namespace eitbench::detail
