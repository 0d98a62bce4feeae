#include "eitbench/jacobian/mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

double signed_area(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
}

std::map<std::pair<int, int>, int> edge_counts(const Triangles& triangles) {
  std::map<std::pair<int, int>, int> count;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = triangles(t, k), v = triangles(t, (k + 1) % 3);
      ++count[{std::min(u, v), std::max(u, v)}];
    }
  return count;
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

double Electrode::length(const Points& nodes) const {
  double sum = 0;
  for (const auto& s : segments) sum += (nodes.row(s[0]) - nodes.row(s[1])).norm();
  return sum;
}

Eigen::VectorXd triangle_areas(const Mesh& mesh) {
  Eigen::VectorXd area(mesh.num_triangles());
  for (int t = 0; t < mesh.num_triangles(); ++t)
    area[t] =
        signed_area(mesh.nodes.row(mesh.triangles(t, 0)), mesh.nodes.row(mesh.triangles(t, 1)),
                    mesh.nodes.row(mesh.triangles(t, 2)));
  return area;
}

Eigen::Vector2d triangle_centroid(const Mesh& mesh, int t) {
  return (mesh.nodes.row(mesh.triangles(t, 0)) + mesh.nodes.row(mesh.triangles(t, 1)) +
          mesh.nodes.row(mesh.triangles(t, 2)))
             .transpose() /
         3.0;
}

MeshQuality measure_quality(const Mesh& mesh) {
  MeshQuality q;
  q.nodes = mesh.num_nodes();
  q.triangles = mesh.num_triangles();
  q.min_angle_deg = 180;
  q.min_area = INFINITY;
  q.max_area = 0;
  const Eigen::VectorXd area = triangle_areas(mesh);
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d p = mesh.nodes.row(mesh.triangles(t, k));
      const Eigen::Vector2d u = Eigen::Vector2d(mesh.nodes.row(mesh.triangles(t, (k + 1) % 3))) - p;
      const Eigen::Vector2d v = Eigen::Vector2d(mesh.nodes.row(mesh.triangles(t, (k + 2) % 3))) - p;
      const double angle =
          std::atan2(std::abs(u.x() * v.y() - u.y() * v.x()), u.dot(v)) * 180 / M_PI;
      q.min_angle_deg = std::min(q.min_angle_deg, angle);
      q.max_angle_deg = std::max(q.max_angle_deg, angle);
    }
    q.min_area = std::min(q.min_area, area[t]);
    q.max_area = std::max(q.max_area, area[t]);
  }
  q.boundary_segments = static_cast<int>(boundary_edges(mesh).size());
  return q;
}

std::vector<std::array<int, 2>> boundary_edges(const Mesh& mesh) {
  std::vector<std::array<int, 2>> out;
  for (const auto& [edge, count] : edge_counts(mesh.triangles))
    if (count == 1) out.push_back({edge.first, edge.second});
  return out;
}

void normalize_mesh(Mesh& mesh) {
  const Eigen::VectorXd area = triangle_areas(mesh);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    if (area[t] < 0) {
      std::swap(mesh.triangles(t, 1), mesh.triangles(t, 2));
      ++mesh.reoriented;
    }

  std::vector<int> used(mesh.num_nodes(), 0);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int n = mesh.triangles(t, k);
      if (n >= 0 && n < mesh.num_nodes()) used[n] = 1;
    }
  if (std::all_of(used.begin(), used.end(), [](int u) { return u == 1; })) return;
  std::vector<int> renumber(mesh.num_nodes(), -1);
  Points kept(std::count(used.begin(), used.end(), 1), 2);
  int next = 0;
  for (int n = 0; n < mesh.num_nodes(); ++n)
    if (used[n]) {
      renumber[n] = next;
      kept.row(next++) = mesh.nodes.row(n);
    }
  auto map = [&](int n) {
    return (n >= 0 && n < static_cast<int>(renumber.size())) ? renumber[n] : -1;
  };
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) mesh.triangles(t, k) = map(mesh.triangles(t, k));
  for (auto& e : mesh.electrodes) {
    if (e.point_node >= 0) e.point_node = map(e.point_node);
    for (auto& s : e.segments) s = {map(s[0]), map(s[1])};
  }
  mesh.nodes = std::move(kept);
}

namespace {

// Indices in range and coordinates finite: what every later check reads.
void check_indices(const Mesh& mesh, const std::string& source) {
  const int n = mesh.num_nodes();
  if (n < 3)
    throw InputError(source, "nodes", "a mesh needs at least 3 nodes, found " + std::to_string(n));
  if (mesh.num_triangles() < 1) throw InputError(source, "triangles", "the mesh has no triangles");
  if (!mesh.nodes.allFinite())
    throw InputError(source, "nodes", "a node coordinate is NaN or infinite");
  for (int t = 0; t < mesh.num_triangles(); ++t)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles(t, k) < 0 || mesh.triangles(t, k) >= n)
        throw InputError(source, "triangle " + std::to_string(t),
                         "refers to a node that does not exist");
}

// Every triangle counter-clockwise with an area above rounding.
void check_areas(const Mesh& mesh, const std::string& source) {
  const Eigen::VectorXd area = triangle_areas(mesh);
  const double scale = area.cwiseAbs().maxCoeff();
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    if (std::abs(area[t]) <= 1e-12 * scale)
      throw InputError(source, "triangle " + std::to_string(t), "has zero area (degenerate)");
    if (area[t] < 0)
      throw InputError(source, "triangle " + std::to_string(t),
                       "is inverted (clockwise while others are counter-clockwise)");
  }
}

// Counter-clockwise triangles that share an edge cross it in opposite directions; two that cross
// it the same way lie on the same side of it, one over the other (a folded mesh, whose inverted
// element normalize_mesh turned round).
void check_folds(const Mesh& mesh, const std::string& source) {
  std::map<std::pair<int, int>, int> crossed_by;  // directed edge -> triangle
  for (int t = 0; t < mesh.num_triangles(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::pair<int, int> edge{mesh.triangles(t, k), mesh.triangles(t, (k + 1) % 3)};
      const auto [it, added] = crossed_by.emplace(edge, t);
      if (!added)
        throw InputError(source, "triangle " + std::to_string(t),
                         "overlaps triangle " + std::to_string(it->second) +
                             " (both lie on the same side of their edge " +
                             std::to_string(edge.first) + "-" + std::to_string(edge.second) +
                             "): the mesh folds over itself");
    }
}

// One piece, every node used (union-find over the triangles' edges).
void check_connected(const Mesh& mesh, const std::string& source) {
  const int n = mesh.num_nodes();
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> used(n, 0);
  for (int t = 0; t < mesh.num_triangles(); ++t)
    for (int k = 0; k < 3; ++k) {
      used[mesh.triangles(t, k)] = 1;
      parent[find_root(parent, mesh.triangles(t, k))] =
          find_root(parent, mesh.triangles(t, (k + 1) % 3));
    }
  int pieces = 0;
  for (int i = 0; i < n; ++i) {
    if (!used[i])
      throw InputError(source, "node " + std::to_string(i), "is not used by any triangle");
    pieces += (find_root(parent, i) == i);
  }
  if (pieces != 1)
    throw InputError(source, "triangles",
                     "the mesh falls into " + std::to_string(pieces) + " disconnected pieces");
}

// At least 4 electrodes, each a node or boundary segments, no node shared between two.
template <class EdgeCounts>
void check_electrodes(const Mesh& mesh, const EdgeCounts& edges, const std::string& source) {
  const int n = mesh.num_nodes();
  if (mesh.num_electrodes() < 4)
    throw InputError(source, "electrodes",
                     "need at least 4 electrodes, found " + std::to_string(mesh.num_electrodes()));
  std::vector<int> owner(n, -1);
  auto claim = [&](int node, int e) {
    if (owner[node] >= 0 && owner[node] != e)
      throw InputError(
          source, "electrode_" + std::to_string(e),
          "shares node " + std::to_string(node) + " with electrode_" + std::to_string(owner[node]));
    owner[node] = e;
  };
  for (int e = 0; e < mesh.num_electrodes(); ++e) {
    const Electrode& el = mesh.electrodes[e];
    const std::string field = "electrode_" + std::to_string(e);
    if (el.is_point()) {
      if (el.point_node < 0 || el.point_node >= n)
        throw InputError(source, field, "is empty or refers to a node that does not exist");
      claim(el.point_node, e);
      continue;
    }
    for (const auto& s : el.segments) {
      if (s[0] < 0 || s[0] >= n || s[1] < 0 || s[1] >= n || s[0] == s[1])
        throw InputError(source, field, "has a segment with invalid nodes");
      auto it = edges.find({std::min(s[0], s[1]), std::max(s[0], s[1])});
      if (it == edges.end() || it->second != 1)
        throw InputError(source, field,
                         "segment " + std::to_string(s[0]) + "-" + std::to_string(s[1]) +
                             " is not on the boundary of the mesh");
      claim(s[0], e);
      claim(s[1], e);
    }
  }
}

}  // namespace

void validate_mesh(const Mesh& mesh, const std::string& source) {
  check_indices(mesh, source);
  check_areas(mesh, source);
  check_folds(mesh, source);
  const auto edges = edge_counts(mesh.triangles);
  for (const auto& [edge, count] : edges)
    if (count > 2)
      throw InputError(source, "triangles",
                       "edge " + std::to_string(edge.first) + "-" + std::to_string(edge.second) +
                           " is shared by " + std::to_string(count) +
                           " triangles (overlapping mesh)");
  check_connected(mesh, source);
  check_electrodes(mesh, edges, source);
}

}  // namespace eitbench
