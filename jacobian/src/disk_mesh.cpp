// The D_L-symmetric disk mesh: Gmsh meshes one fundamental sector, the group replicates it.
//
// The fundamental sector is 0 <= theta <= pi/L: from the centre line of electrode 0 (a mirror axis)
// to the middle of the next gap (another mirror axis). Its apex cannot be meshed on its own: any
// triangle there would have an angle <= pi/L. The centre is therefore built by hand from 2L
// triangles that straddle the electrode axes, L "spokes" (O, G_{j-1}, G_j) with G_j on the gap
// axes, and L equilateral "caps" (G_{j-1}, E_j, G_j) with E_j on the electrode axes. Gmsh meshes
// the rest of the sector with the cap's edge G_0-E_0 held as one segment, and with the arc nodes on
// the circle. Replicating the sector by rotations and reflections then gives a conforming mesh
// whose node set and triangle set are exactly invariant under D_L.
#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>

#include "eitbench/jacobian/constants.h"
#include "eitbench/jacobian/disk_mesh.h"
#include "eitbench/jacobian/error.h"
#include "gmsh_session.h"

namespace eitbench {
namespace {

using detail::GmshSession;
using detail::SizeSet;

// A mesh of the sector in polar form, so that its images can be computed exactly.
struct SectorMesh {
  std::vector<double> r, phi;
  std::vector<std::array<int, 3>> triangles;
  int e0 = -1, g0 = -1;  // the cap's corners E_0 (on theta = 0) and G_0 (on theta = pi/L)
};

SectorMesh mesh_sector(const DiskMeshOptions& o, const SizeSet& h, double a, double b) {
  const double R = o.radius;
  const double gap = kPi / o.electrodes;                          // sector angle
  const double half = kPi * o.electrode_coverage / o.electrodes;  // half the electrode's angle

  std::lock_guard<std::mutex> lock(detail::gmsh_mutex());
  GmshSession session;
  gmsh::model::add("sector");
  namespace geo = gmsh::model::geo;
  const int p_o = geo::addPoint(0, 0, 0);
  const int p_e0 = geo::addPoint(a, 0, 0);
  const int p_a = geo::addPoint(R, 0, 0);
  const int p_edge = geo::addPoint(R * std::cos(half), R * std::sin(half), 0);
  const int p_b = geo::addPoint(R * std::cos(gap), R * std::sin(gap), 0);
  const int p_g0 = geo::addPoint(b * std::cos(gap), b * std::sin(gap), 0);
  const int axis = geo::addLine(p_e0, p_a);
  const int electrode_arc = geo::addCircleArc(p_a, p_o, p_edge);
  const int gap_arc = geo::addCircleArc(p_edge, p_o, p_b);
  const int gap_axis = geo::addLine(p_b, p_g0);
  const int cap = geo::addLine(p_g0, p_e0);
  const int loop = geo::addCurveLoop({axis, electrode_arc, gap_arc, gap_axis, cap});
  geo::addPlaneSurface({loop});
  geo::mesh::setTransfiniteCurve(cap, 2);
  geo::synchronize();

  const int rim_size = detail::distance_threshold({double(electrode_arc), double(gap_arc)}, {},
                                                  h.boundary, h.centre, 0.45 * R);
  const int edge_size = detail::distance_threshold({}, {double(p_edge)}, h.edge, h.centre,
                                                   6.0 * (h.boundary - h.edge) + 0.1 * R);
  // Grade from the short cap edge G_0-E_0 to the centre size, or the angles next to it suffer.
  const double cap_side = 2 * b * std::sin(gap);
  const int cap_size = detail::distance_threshold({}, {double(p_e0), double(p_g0)}, cap_side,
                                                  h.centre, 3.0 * (h.centre - cap_side) + 1e-3 * R);
  detail::use_size_fields({double(rim_size), double(edge_size), double(cap_size)});
  gmsh::model::mesh::generate(2);

  std::vector<std::size_t> node_tags, element_tags, element_nodes;
  std::vector<double> coords, parametric;
  gmsh::model::mesh::getNodes(node_tags, coords, parametric, -1, -1, false, false);
  gmsh::model::mesh::getElementsByType(2, element_tags, element_nodes);

  // Only nodes that triangles use (the arc centre is a geometry point, not part of the mesh).
  std::map<std::size_t, std::array<double, 2>> xy;
  for (std::size_t i = 0; i < node_tags.size(); ++i)
    xy[node_tags[i]] = {coords[3 * i], coords[3 * i + 1]};
  std::map<std::size_t, int> local;
  SectorMesh out;
  const double tol = 1e-9 * R;
  auto local_index = [&](std::size_t tag) {
    auto [it, inserted] = local.emplace(tag, static_cast<int>(out.r.size()));
    if (inserted) {
      const auto [x, y] = xy.at(tag);
      double r = std::hypot(x, y);
      double phi = std::atan2(y, x);
      // Snap nodes on the mirror axes and the rim, so that their images coincide exactly.
      if (std::abs(y) <= tol) phi = 0.0;
      if (std::abs(x * std::sin(gap) - y * std::cos(gap)) <= tol) phi = gap;
      if (std::abs(r - R) <= tol) r = R;
      out.r.push_back(r);
      out.phi.push_back(phi);
    }
    return it->second;
  };
  for (std::size_t t = 0; t < element_tags.size(); ++t) {
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) tri[k] = local_index(element_nodes[3 * t + k]);
    out.triangles.push_back(tri);
  }
  auto find_node = [&](double x, double y) {
    for (std::size_t i = 0; i < out.r.size(); ++i)
      if (std::hypot(out.r[i] * std::cos(out.phi[i]) - x, out.r[i] * std::sin(out.phi[i]) - y) <=
          tol)
        return static_cast<int>(i);
    throw std::runtime_error("disk mesher: Gmsh dropped a corner of the sector");
  };
  out.e0 = find_node(a, 0);
  out.g0 = find_node(b * std::cos(gap), b * std::sin(gap));
  return out;
}

}  // namespace

namespace {

// The disk as 2L copies of the sector: copy c covers c*pi/L <= theta <= (c+1)*pi/L, even copies
// rotations of the sector, odd ones its mirror images. A node on an axis belongs to two
// neighbouring copies; the even copy owns it.
struct Replicas {
  std::vector<std::array<double, 2>> nodes{{0.0, 0.0}};  // node 0: the centre
  std::vector<int> global;                               // (copy, local node) -> node
  int copies = 0, n_local = 0;
  int id(int c, int k) const {
    return global[static_cast<std::size_t>(((c % copies) + copies) % copies) * n_local + k];
  }
};

Replicas replicate_nodes(const SectorMesh& sector, int L) {
  const double gap = kPi / L;
  Replicas out;
  out.n_local = static_cast<int>(sector.r.size());
  out.copies = 2 * L;
  out.global.assign(static_cast<std::size_t>(out.copies) * out.n_local, -1);
  auto angle_of = [&](int c, int k) {
    return (c % 2 == 0) ? c * gap + sector.phi[k] : (c + 1) * gap - sector.phi[k];
  };
  for (int c = 0; c < out.copies; ++c) {
    for (int k = 0; k < out.n_local; ++k) {
      int owner = c;
      if (c % 2 == 1 && sector.phi[k] == 0.0) owner = (c + 1) % out.copies;  // on electrode axis
      if (c % 2 == 1 && sector.phi[k] == gap) owner = c - 1;                 // on gap axis
      int& slot = out.global[static_cast<std::size_t>(owner) * out.n_local + k];
      if (slot < 0) {
        const double theta = angle_of(owner, k);
        slot = static_cast<int>(out.nodes.size());
        out.nodes.push_back({sector.r[k] * std::cos(theta), sector.r[k] * std::sin(theta)});
      }
      out.global[static_cast<std::size_t>(c) * out.n_local + k] = slot;
    }
  }
  return out;
}

// Every copy's triangles, then the two that close each electrode's cap at the centre.
std::vector<std::array<int, 3>> replicate_triangles(const SectorMesh& sector, const Replicas& r,
                                                    int L) {
  std::vector<std::array<int, 3>> triangles;
  for (int c = 0; c < r.copies; ++c) {
    for (const auto& t : sector.triangles) {
      std::array<int, 3> g{r.id(c, t[0]), r.id(c, t[1]), r.id(c, t[2])};
      if (c % 2 == 1) std::swap(g[1], g[2]);  // a reflection reverses orientation
      triangles.push_back(g);
    }
  }
  for (int j = 0; j < L; ++j) {
    const int g_prev = r.id(2 * j - 2, sector.g0);  // G_{j-1}, on the gap axis at (2j-1) pi/L
    const int g_next = r.id(2 * j, sector.g0);      // G_j, at (2j+1) pi/L
    const int e = r.id(2 * j, sector.e0);           // E_j, on electrode j's axis
    triangles.push_back({0, g_prev, g_next});
    triangles.push_back({g_prev, e, g_next});
  }
  return triangles;
}

// Nodes and triangles into a Mesh, every triangle counter-clockwise (Gmsh's sector orientation is
// not promised); `triangles` is reoriented in place to match.
Mesh to_mesh(const std::vector<std::array<double, 2>>& nodes,
             std::vector<std::array<int, 3>>& triangles) {
  Mesh mesh;
  mesh.nodes.resize(static_cast<Eigen::Index>(nodes.size()), 2);
  for (std::size_t i = 0; i < nodes.size(); ++i) mesh.nodes.row(i) << nodes[i][0], nodes[i][1];
  mesh.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    auto& tri = triangles[t];
    const Eigen::Vector2d p0 = mesh.nodes.row(tri[0]), p1 = mesh.nodes.row(tri[1]),
                          p2 = mesh.nodes.row(tri[2]);
    const double cross = (p1 - p0).x() * (p2 - p0).y() - (p1 - p0).y() * (p2 - p0).x();
    if (cross < 0) std::swap(tri[1], tri[2]);
    mesh.triangles.row(t) << tri[0], tri[1], tri[2];
  }
  return mesh;
}

// Electrode e: the rim segments whose midpoint lies within its arc, sorted counter-clockwise.
// The electrode edges are nodes, so every rim segment is either wholly under an electrode or
// wholly in a gap.
void assign_electrodes(Mesh& mesh, int L, double coverage) {
  const double gap = kPi / L, half = kPi * coverage / L;
  mesh.electrodes.resize(L);
  for (const auto& edge : boundary_edges(mesh)) {
    const Eigen::Vector2d mid =
        0.5 * (mesh.nodes.row(edge[0]) + mesh.nodes.row(edge[1])).transpose();
    const double theta = std::atan2(mid.y(), mid.x());
    const int e = static_cast<int>(std::lround(theta / (2 * gap))) % L;
    const int nearest = (e + L) % L;
    double offset = std::remainder(theta - 2 * gap * nearest, 2 * kPi);
    if (std::abs(offset) < half) mesh.electrodes[nearest].segments.push_back(edge);
  }
  for (auto& electrode : mesh.electrodes) {  // along the rim, counter-clockwise
    if (electrode.segments.empty())
      throw std::runtime_error("disk mesher: an electrode has no segment");
    auto angle = [&](const std::array<int, 2>& s) {
      const Eigen::Vector2d m = 0.5 * (mesh.nodes.row(s[0]) + mesh.nodes.row(s[1])).transpose();
      return std::atan2(m.y(), m.x());
    };
    const double centre = angle(electrode.segments.front());
    std::sort(electrode.segments.begin(), electrode.segments.end(),
              [&](const auto& s, const auto& t) {
                return std::remainder(angle(s) - centre, 2 * kPi) <
                       std::remainder(angle(t) - centre, 2 * kPi);
              });
  }
}

}  // namespace

Mesh generate_disk_mesh(const DiskMeshOptions& o) {
  o.validate();
  const int L = o.electrodes;

  const double R = o.radius;
  const double gap = kPi / L;
  SizeSet h = detail::sizes_for(o.density);
  h = {h.centre * R * o.size_factor, h.boundary * R * o.size_factor, h.edge * R * o.size_factor};
  // At least one segment across each half electrode, so narrow electrodes are still resolved.
  h.edge = std::min(h.edge, R * kPi * o.electrode_coverage / L);
  h.boundary = std::max(h.boundary, h.edge);

  // Spoke length b and cap corner a: an equilateral cap whose side is about 0.7 of the centre size,
  // with spokes no longer than 1.2 centre sizes nor 0.3 R.
  const double b = std::min({0.7 * h.centre / (2 * std::sin(gap)), 1.2 * h.centre, 0.3 * R});
  const double a = b * (std::cos(gap) + std::sqrt(3.0) * std::sin(gap));
  if (a > 0.6 * R)
    throw InputError("DiskMeshOptions", "size_factor", "the mesh is too coarse for this disk");

  SectorMesh sector;
  try {
    sector = mesh_sector(o, h, a, b);
  } catch (const std::runtime_error&) {
    throw;
  } catch (...) {
    throw std::runtime_error("disk mesher: Gmsh failed to mesh the sector");
  }

  const Replicas replicas = replicate_nodes(sector, L);
  std::vector<std::array<int, 3>> triangles = replicate_triangles(sector, replicas, L);
  Mesh mesh = to_mesh(replicas.nodes, triangles);
  assign_electrodes(mesh, L, o.electrode_coverage);
  return mesh;
}

}  // namespace eitbench
