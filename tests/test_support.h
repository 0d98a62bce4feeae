#pragma once
// Helpers shared by the suites: cached meshes, and the D_L group acting on a mesh's elements.
#include <Eigen/Core>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "eitbench/jacobian.h"

namespace eitbench::testing {

// The background conductivity (S/m) of the suites' media with touches.
inline constexpr double kBackground = 0.05;

// The KTC2023 training set beside the repository (not committed: tests that need it skip).
inline std::string ktc_folder() {
  return std::string(EITBENCH_SOURCE_DIR) + "/../shared/data/ktc2023";
}

// "source.field" of the InputError that `call` throws, so that a test can check that an error
// names the options struct and the field at fault; "no InputError" when it throws none.
template <class Call>
std::string input_error_at(Call call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.source() + "." + e.field();
  }
  return "no InputError";
}

// Element conductivities uniform in [0.5, 2]: a generic, far from symmetric medium.
inline Eigen::VectorXd random_conductivity(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  Eigen::VectorXd sigma(n);
  for (auto& s : sigma) s = u(rng);
  return sigma;
}

inline const Mesh& disk(int electrodes, MeshDensity density, double coverage = 0.5) {
  static std::map<std::tuple<int, int, double>, Mesh> cache;
  const auto key = std::make_tuple(electrodes, static_cast<int>(density), coverage);
  auto it = cache.find(key);
  if (it == cache.end()) {
    DiskMeshOptions o;
    o.electrodes = electrodes;
    o.density = density;
    o.electrode_coverage = coverage;
    it = cache.emplace(key, generate_disk_mesh(o)).first;
  }
  return it->second;
}

// The image of point p under the group element "rotate by s electrode steps, after mirroring about
// the x axis when `mirror`".
inline Eigen::Vector2d transform_point(const Eigen::Vector2d& p, int L, int s, bool mirror) {
  const Eigen::Vector2d q(p.x(), mirror ? -p.y() : p.y());
  const double a = 2 * M_PI * s / L;
  return {std::cos(a) * q.x() - std::sin(a) * q.y(), std::sin(a) * q.x() + std::cos(a) * q.y()};
}

// Index of the node at p, or -1: exact search by rounding to a 1e-9 lattice (and its neighbours).
class NodeLocator {
 public:
  explicit NodeLocator(const Points& nodes) : nodes_(nodes) {
    for (int i = 0; i < nodes.rows(); ++i) cells_.emplace(cell(nodes.row(i)), i);
  }
  int find(const Eigen::Vector2d& p, double tol) const {
    const auto c = cell(p);
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy) {
        auto [lo, hi] = cells_.equal_range({c.first + dx, c.second + dy});
        for (auto it = lo; it != hi; ++it)
          if ((Eigen::Vector2d(nodes_.row(it->second)) - p).norm() <= tol) return it->second;
      }
    return -1;
  }

 private:
  static std::pair<long, long> cell(const Eigen::Vector2d& p) {
    return {std::lround(p.x() * 1e6), std::lround(p.y() * 1e6)};
  }
  const Points& nodes_;
  std::multimap<std::pair<long, long>, int> cells_;
};

// Element permutation of a group element: image[t] is the triangle that triangle t maps onto, or
// -1 when the mesh is not symmetric.
// Each triangle by its sorted node indices.
inline std::map<std::array<int, 3>, int> triangles_by_nodes(const Mesh& mesh) {
  std::map<std::array<int, 3>, int> by_nodes;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    std::array<int, 3> key{mesh.triangles(t, 0), mesh.triangles(t, 1), mesh.triangles(t, 2)};
    std::sort(key.begin(), key.end());
    by_nodes[key] = t;
  }
  return by_nodes;
}

inline std::vector<int> element_image(const Mesh& mesh, int s, bool mirror, double tol = 1e-12) {
  const int L = mesh.num_electrodes();
  const NodeLocator nodes(mesh.nodes);
  const auto by_nodes = triangles_by_nodes(mesh);
  std::vector<int> image(mesh.num_triangles(), -1);
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    std::array<int, 3> key{};
    for (int k = 0; k < 3; ++k)
      key[k] = nodes.find(transform_point(mesh.nodes.row(mesh.triangles(t, k)), L, s, mirror), tol);
    std::sort(key.begin(), key.end());
    auto it = by_nodes.find(key);
    if (key[0] >= 0 && it != by_nodes.end()) image[t] = it->second;
  }
  return image;
}

}  // namespace eitbench::testing
