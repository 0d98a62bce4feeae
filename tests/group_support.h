#pragma once
// The sensor's group acting on a symmetric mesh's conductivity, for the suites that check frame
// actions against the forward model.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "eitbench/augment/symmetry.h"
#include "test_support.h"

namespace eitbench::testing {

// sigma moved by g on a symmetric mesh: the triangle t goes to where g sends it.
inline Eigen::VectorXd move_conductivity(const Mesh& mesh, const Eigen::VectorXd& sigma,
                                         const GroupElement& g) {
  const int L = mesh.num_electrodes();
  const NodeLocator nodes(mesh.nodes);
  const auto by_nodes = triangles_by_nodes(mesh);
  Eigen::VectorXd moved = Eigen::VectorXd::Constant(sigma.size(), NAN);
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    std::array<int, 3> key{};
    for (int k = 0; k < 3; ++k)
      key[k] = nodes.find(transform_point(mesh.nodes.row(mesh.triangles(t, k)), g, L), 1e-12);
    std::sort(key.begin(), key.end());
    moved[by_nodes.at(key)] = sigma[t];
  }
  return moved;
}

}  // namespace eitbench::testing
