// Rectangles and ellipses meshed by Gmsh: the boundary cut at every electrode edge (and at the
// corners or the axis vertices), one curve a stretch, each stretch an electrode's or a gap's.
#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/shape_mesh.h"
#include "gmsh_session.h"

namespace eitbench {
namespace {

struct Breakpoint {
  double s;      // fraction of the perimeter
  bool edge;     // an electrode's edge (meshed finest)
  int tag = -1;  // its Gmsh point
};

// The electrode centres: the user's, or evenly spaced half a step from the +x axis.
std::vector<double> centres(const ShapeMeshOptions& o) {
  if (!o.electrode_positions.empty()) return o.electrode_positions;
  std::vector<double> c(o.electrodes);
  for (int e = 0; e < o.electrodes; ++e) c[e] = (e + 0.5) / o.electrodes;
  return c;
}

std::vector<Breakpoint> breakpoints(const ShapeMeshOptions& o, const std::vector<double>& c) {
  const double w = o.electrode_coverage / o.electrodes, W = o.width, H = o.height;
  std::vector<Breakpoint> out;
  for (double p : c)
    for (double end : {p - 0.5 * w, p + 0.5 * w}) out.push_back({end - std::floor(end), true});
  const double P = 2 * (W + H);  // the rectangle's corners, or the ellipse's vertices
  const std::vector<double> corners =
      o.shape == SensorShape::rectangle
          ? std::vector<double>{0.5 * H / P, (0.5 * H + W) / P, (1.5 * H + W) / P,
                                (1.5 * H + 2 * W) / P}
          : std::vector<double>{0.0, 0.25, 0.5, 0.75};
  for (double s : corners) out.push_back({s, false});
  std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.s < y.s; });
  std::vector<Breakpoint> merged;  // an electrode edge on a corner is one point
  for (const auto& p : out) {
    if (!merged.empty() && p.s - merged.back().s < 1e-12)
      merged.back().edge = merged.back().edge || p.edge;
    else
      merged.push_back(p);
  }
  if (merged.size() > 1 && merged.front().s + 1 - merged.back().s < 1e-12) {
    merged.front().edge = merged.front().edge || merged.back().edge;
    merged.pop_back();
  }
  return merged;
}

// The electrode a stretch of boundary from s0 to s1 belongs to, or -1 for a gap.
int electrode_of(double s0, double s1, const std::vector<double>& c, double w) {
  const double mid = 0.5 * (s0 + s1);
  for (std::size_t e = 0; e < c.size(); ++e)
    if (std::abs(std::remainder(mid - c[e], 1.0)) < 0.5 * w) return static_cast<int>(e);
  return -1;
}

void set_sizes(const detail::SizeSet& h, double R, const std::vector<int>& curves,
               const std::vector<int>& edge_points) {
  const int rim = detail::distance_threshold(std::vector<double>(curves.begin(), curves.end()), {},
                                             h.boundary, h.centre, 0.45 * R);
  const int edge =
      detail::distance_threshold({}, std::vector<double>(edge_points.begin(), edge_points.end()),
                                 h.edge, h.centre, 6.0 * (h.boundary - h.edge) + 0.1 * R);
  detail::use_size_fields({double(rim), double(edge)});
}

// Gmsh's nodes, triangles and the line elements of each electrode's curves, as a Mesh.
Mesh read_gmsh_model(const std::vector<std::vector<int>>& electrode_curves) {
  std::vector<std::size_t> node_tags, element_tags, element_nodes;
  std::vector<double> coords, parametric;
  gmsh::model::mesh::getNodes(node_tags, coords, parametric, -1, -1, false, false);
  std::map<std::size_t, int> index;
  Mesh mesh;
  mesh.nodes.resize(static_cast<Eigen::Index>(node_tags.size()), 2);
  for (std::size_t i = 0; i < node_tags.size(); ++i) {
    index[node_tags[i]] = static_cast<int>(i);
    mesh.nodes.row(static_cast<Eigen::Index>(i)) << coords[3 * i], coords[3 * i + 1];
  }
  gmsh::model::mesh::getElementsByType(2, element_tags, element_nodes);
  mesh.triangles.resize(static_cast<Eigen::Index>(element_tags.size()), 3);
  for (std::size_t t = 0; t < element_tags.size(); ++t)
    for (int k = 0; k < 3; ++k)
      mesh.triangles(static_cast<Eigen::Index>(t), k) = index.at(element_nodes[3 * t + k]);
  for (const auto& curves : electrode_curves) {
    Electrode electrode;
    for (int curve : curves) {
      std::vector<int> types;
      std::vector<std::vector<std::size_t>> tags, nodes;
      gmsh::model::mesh::getElements(types, tags, nodes, 1, curve);
      for (std::size_t i = 0; i < types.size(); ++i) {
        if (types[i] != 1) continue;  // 2-node lines
        for (std::size_t k = 0; k < tags[i].size(); ++k)
          electrode.segments.push_back({index.at(nodes[i][2 * k]), index.at(nodes[i][2 * k + 1])});
      }
    }
    mesh.electrodes.push_back(electrode);
  }
  return mesh;
}

Mesh mesh_shape(const ShapeMeshOptions& o) {
  const std::vector<double> c = centres(o);
  std::vector<Breakpoint> cuts = breakpoints(o, c);
  const double w = o.electrode_coverage / o.electrodes;
  const double R = 0.5 * std::sqrt(o.width * o.height);
  detail::SizeSet h = detail::sizes_for(o.density);
  h = {h.centre * R * o.size_factor, h.boundary * R * o.size_factor, h.edge * R * o.size_factor};
  const double a = 0.5 * o.width, b = 0.5 * o.height;  // Ramanujan's ellipse perimeter (1e-5)
  const double perimeter = o.shape == SensorShape::rectangle
                               ? 4 * (a + b)
                               : M_PI * (3 * (a + b) - std::sqrt((3 * a + b) * (a + 3 * b)));
  // At least one segment across each half electrode, as on the disk.
  h.edge = std::min(h.edge, 0.5 * w * perimeter);
  h.boundary = std::max(h.boundary, h.edge);

  std::lock_guard<std::mutex> lock(detail::gmsh_mutex());
  detail::GmshSession session;
  gmsh::model::add("sensor");
  namespace geo = gmsh::model::geo;
  std::vector<int> edge_points;
  for (auto& p : cuts) {
    const PerimeterPoint q = perimeter_point(o, p.s);
    p.tag = geo::addPoint(q.x, q.y, 0);
    if (p.edge) edge_points.push_back(p.tag);
  }
  const bool wide = o.width >= o.height;
  const int centre = geo::addPoint(0, 0, 0);
  const int major = wide ? geo::addPoint(o.width, 0, 0) : geo::addPoint(0, o.height, 0);
  std::vector<int> curves;
  std::vector<std::vector<int>> electrode_curves(o.electrodes);
  for (std::size_t k = 0; k < cuts.size(); ++k) {
    const Breakpoint& from = cuts[k];
    const Breakpoint& to = cuts[(k + 1) % cuts.size()];
    const int curve = o.shape == SensorShape::rectangle
                          ? geo::addLine(from.tag, to.tag)
                          : geo::addEllipseArc(from.tag, centre, major, to.tag);
    curves.push_back(curve);
    const double end = k + 1 < cuts.size() ? to.s : to.s + 1;
    const int e = electrode_of(from.s, end, c, w);
    if (e >= 0) electrode_curves[e].push_back(curve);
  }
  geo::addPlaneSurface({geo::addCurveLoop(curves)});
  geo::synchronize();
  set_sizes(h, R, curves, edge_points);
  gmsh::model::mesh::generate(2);
  return read_gmsh_model(electrode_curves);
}

}  // namespace

Mesh generate_shape_mesh(const ShapeMeshOptions& o) {
  o.validate();
  if (o.shape == SensorShape::disk && o.electrode_positions.empty())
    return generate_disk_mesh(
        {o.electrodes, o.density, 0.5 * o.width, o.electrode_coverage, o.size_factor});
  Mesh mesh;
  try {
    mesh = mesh_shape(o);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("shape mesher: Gmsh failed: ") + e.what());
  } catch (const std::string& e) {  // Gmsh's API throws its messages
    throw std::runtime_error("shape mesher: Gmsh failed: " + e);
  } catch (...) {
    throw std::runtime_error("shape mesher: Gmsh failed");
  }
  normalize_mesh(mesh);  // drops the construction points, orients every triangle
  mesh.reoriented = 0;   // Gmsh's own orientation is not the user's concern
  validate_mesh(mesh, "shape mesher");
  return mesh;
}

}  // namespace eitbench
