#include "neighbour_graphs.h"

#include <algorithm>
#include <map>

namespace eitbench::detail {

std::vector<int> unknown_of_pixel(const std::vector<int>& pixels, int num_pixels) {
  std::vector<int> unknown(static_cast<std::size_t>(num_pixels), -1);
  for (std::size_t j = 0; j < pixels.size(); ++j) unknown[pixels[j]] = static_cast<int>(j);
  return unknown;
}

std::vector<InteriorEdge> interior_edges(const Mesh& mesh) {
  std::map<std::pair<int, int>, int> first;  // edge -> the first triangle seen on it
  std::vector<InteriorEdge> edges;
  for (int t = 0; t < mesh.num_triangles(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles(t, k), b = mesh.triangles(t, (k + 1) % 3);
      const auto [it, fresh] = first.emplace(std::make_pair(std::min(a, b), std::max(a, b)), t);
      if (!fresh) edges.push_back({it->second, t, a, b});
    }
  return edges;
}

}  // namespace eitbench::detail
