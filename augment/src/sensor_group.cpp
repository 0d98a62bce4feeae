// The sensor's symmetry group: candidates from electrode 0's possible images, each checked on every
// electrode (centre, length, ends) and every boundary node.
#include "eitbench/augment/sensor_group.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>

#include "eitbench/jacobian/constants.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

using Segment = std::array<Eigen::Vector2d, 2>;

Eigen::Vector2d node(const Mesh& mesh, int i) {
  return mesh.nodes.row(i).transpose();
}

// What the search compares: the boundary, and each electrode's centre, length and two ends.
struct Layout {
  std::vector<Eigen::Vector2d> boundary_nodes;
  std::vector<Segment> boundary;
  double median_segment = 0;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> electrode_centre;
  std::vector<double> electrode_length;
  std::vector<Segment> electrode_ends;
};

void measure_boundary(const Mesh& mesh, Layout& out) {
  std::vector<double> lengths;
  std::vector<bool> on_boundary(static_cast<std::size_t>(mesh.num_nodes()), false);
  for (const auto& [u, v] : boundary_edges(mesh)) {
    out.boundary.push_back({node(mesh, u), node(mesh, v)});
    lengths.push_back((out.boundary.back()[1] - out.boundary.back()[0]).norm());
    on_boundary[u] = on_boundary[v] = true;
  }
  for (int i = 0; i < mesh.num_nodes(); ++i)
    if (on_boundary[i]) out.boundary_nodes.push_back(node(mesh, i));
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  out.median_segment = lengths.empty() ? 0 : lengths[lengths.size() / 2];
}

void measure_electrodes(const Mesh& mesh, Layout& out) {
  for (const Electrode& e : mesh.electrodes) {
    if (e.is_point()) {
      const Eigen::Vector2d p = node(mesh, e.point_node);
      out.electrode_centre.push_back(p);
      out.electrode_length.push_back(0);
      out.electrode_ends.push_back({p, p});
      continue;
    }
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    double length = 0;
    std::map<int, int> uses;
    for (const auto& s : e.segments) {
      const double l = (node(mesh, s[1]) - node(mesh, s[0])).norm();
      sum += 0.5 * l * (node(mesh, s[0]) + node(mesh, s[1]));
      length += l;
      ++uses[s[0]];
      ++uses[s[1]];
    }
    std::vector<Eigen::Vector2d> ends;
    for (const auto& [n, count] : uses)
      if (count == 1) ends.push_back(node(mesh, n));
    const Eigen::Vector2d centre = sum / length;
    out.electrode_centre.push_back(centre);
    out.electrode_length.push_back(length);
    out.electrode_ends.push_back(ends.size() == 2 ? Segment{ends[0], ends[1]}
                                                  : Segment{centre, centre});  // a closed ring
  }
}

Layout measure(const Mesh& mesh) {
  Layout out;
  measure_boundary(mesh, out);
  measure_electrodes(mesh, out);
  const Eigen::VectorXd areas = triangle_areas(mesh);
  for (int t = 0; t < mesh.num_triangles(); ++t)
    out.centre += areas[t] * triangle_centroid(mesh, t);
  out.centre /= areas.sum();
  return out;
}

double angle_of(const Eigen::Vector2d& v) {
  return std::atan2(v.y(), v.x());
}

Eigen::Matrix2d rotation(double a) {
  Eigen::Matrix2d m;
  m << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return m;
}
Eigen::Matrix2d reflection(double axis) {  // about the line through the origin at angle `axis`
  Eigen::Matrix2d m;
  m << std::cos(2 * axis), std::sin(2 * axis), std::sin(2 * axis), -std::cos(2 * axis);
  return m;
}

// The rotation (or reflection) about the centre that takes electrode 0's centre onto electrode
// k's, when they are at the same distance from it.
std::optional<Isometry> candidate(const Layout& l, int k, bool mirror, double tol) {
  const Eigen::Vector2d a = l.electrode_centre[0] - l.centre, b = l.electrode_centre[k] - l.centre;
  if (std::abs(a.norm() - b.norm()) > tol) return std::nullopt;
  const double from = angle_of(a), to = angle_of(b);
  return Isometry{mirror ? reflection(0.5 * (from + to)) : rotation(to - from), l.centre};
}

double segment_distance(const Eigen::Vector2d& p, const Segment& s) {
  const Eigen::Vector2d d = s[1] - s[0];
  const double t = std::clamp((p - s[0]).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (s[0] + t * d - p).norm();
}

double ends_distance(const Segment& mapped, const Segment& target) {
  const double straight = std::max((mapped[0] - target[0]).norm(), (mapped[1] - target[1]).norm());
  const double crossed = std::max((mapped[0] - target[1]).norm(), (mapped[1] - target[0]).norm());
  return std::min(straight, crossed);
}

// Why electrode e does not land on electrode j under `map`, or nothing when it does.
std::optional<std::string> electrode_mismatch(const Layout& l, const Isometry& map, int e, int j,
                                              double tol) {
  const double centre = (map(l.electrode_centre[e]) - l.electrode_centre[j]).norm();
  if (centre > tol) return fmt::format("its centre lands {:.3g} from electrode {}'s", centre, j);
  const double length = std::abs(l.electrode_length[e] - l.electrode_length[j]);
  if (length > tol)
    return fmt::format("it is {:.4g} long, electrode {} {:.4g}", l.electrode_length[e], j,
                       l.electrode_length[j]);
  const Segment ends{map(l.electrode_ends[e][0]), map(l.electrode_ends[e][1])};
  const double off = ends_distance(ends, l.electrode_ends[j]);
  if (off > tol) return fmt::format("its ends land {:.3g} from electrode {}'s", off, j);
  return std::nullopt;
}

// The first boundary node that `map` takes off the boundary, as a message.
std::optional<std::string> boundary_mismatch(const Layout& l, const Isometry& map, double tol) {
  for (const Eigen::Vector2d& p : l.boundary_nodes) {
    const Eigen::Vector2d q = map(p);
    double best = INFINITY;
    for (const Segment& s : l.boundary) best = std::min(best, segment_distance(q, s));
    if (best > tol)
      return fmt::format("the boundary point ({:.4g}, {:.4g}) lands {:.3g} off the boundary", p.x(),
                         p.y(), best);
  }
  return std::nullopt;
}

// The electrode each electrode lands on (within tol), or nothing when one lands on none.
std::optional<std::vector<int>> electrode_permutation(const Layout& l, const Isometry& map,
                                                      double tol) {
  const int L = static_cast<int>(l.electrode_centre.size());
  std::vector<int> perm(L, -1);
  std::vector<bool> taken(L, false);
  for (int e = 0; e < L; ++e) {
    const Eigen::Vector2d q = map(l.electrode_centre[e]);
    int best = 0;
    for (int j = 1; j < L; ++j)
      if ((q - l.electrode_centre[j]).norm() < (q - l.electrode_centre[best]).norm()) best = j;
    if (taken[best] || electrode_mismatch(l, map, e, best, tol)) return std::nullopt;
    taken[best] = true;
    perm[e] = best;
  }
  return perm;
}

// The element of D_L (on indices) whose electrode map is `perm`, or nothing when there is none: the
// electrodes are not numbered along the boundary.
std::optional<GroupElement> index_element(const std::vector<int>& perm, bool mirror) {
  const int L = static_cast<int>(perm.size());
  const GroupElement g{(L - perm[0]) % L, mirror};  // the one sending electrode 0 to perm[0]
  for (int e = 0; e < L; ++e)
    if (perm[e] != electrode_image(g, e, L)) return std::nullopt;
  return g;
}

double turn_of(const Isometry& m) {  // rotation angle in [0, 2 pi), or twice the mirror's axis
  const double a = std::atan2(m.linear(1, 0), m.linear(0, 0));
  return a < -1e-12 ? a + 2 * kPi : std::max(a, 0.0);
}

}  // namespace

void SymmetrySearchOptions::validate() const {
  if (!(relative_tolerance > 0 && relative_tolerance <= 1))
    throw InputError("SymmetrySearchOptions", "relative_tolerance", "must be in (0, 1]");
}

std::string Isometry::describe() const {
  const double turn = turn_of(*this) * 180 / kPi;
  const double angle = is_reflection() ? 0.5 * turn : turn, full = is_reflection() ? 180 : 360;
  const bool zero = angle < 1e-6 || full - angle < 1e-6;  // round-off about the +x axis
  return fmt::format(is_reflection() ? "mirror, axis at {:.4g} deg" : "rotation by {:.4g} deg",
                     zero ? 0.0 : angle);
}

bool SensorGroup::has_reflections() const {
  return std::any_of(elements.begin(), elements.end(),
                     [](const SensorSymmetry& s) { return s.map.is_reflection(); });
}

std::string SensorGroup::name() const {
  const int rotations = has_reflections() ? order() / 2 : order();
  if (has_reflections()) return "D" + std::to_string(rotations);
  return rotations == 1 ? "trivial" : "C" + std::to_string(rotations);
}

std::vector<SensorSymmetry> SensorGroup::generators() const {
  std::vector<SensorSymmetry> out;
  for (const auto& s : elements)  // rotations come sorted by angle: the first after the identity
    if (!s.map.is_reflection() && s.element != GroupElement{}) {
      out.push_back(s);
      break;
    }
  for (const auto& s : elements)
    if (s.map.is_reflection()) {
      out.push_back(s);
      break;
    }
  return out;
}

const SensorSymmetry* SensorGroup::find(const GroupElement& g) const {
  for (const auto& s : elements)
    if (s.element == g) return &s;
  return nullptr;
}

std::vector<GroupElement> SensorGroup::frame_elements() const {
  std::vector<GroupElement> out;
  for (const auto& s : elements) out.push_back(s.element);
  return out;
}

ShapedSensor shaped_sensor(const Mesh& mesh, int image_size, const SymmetrySearchOptions& options,
                           const std::string& source) {
  return {find_sensor_group(mesh, options, source), PixelGrid::covering(mesh, image_size)};
}

SensorGroup find_sensor_group(const Mesh& mesh, const SymmetrySearchOptions& options,
                              const std::string& source) {
  options.validate();
  const Layout l = measure(mesh);
  const int L = mesh.num_electrodes();
  SensorGroup group;
  group.electrodes = L;
  group.centre = l.centre;
  group.tolerance = options.relative_tolerance * l.median_segment;
  if ((l.electrode_centre[0] - l.centre).norm() <= group.tolerance)
    throw InputError(source, "electrode_0", "lies at the sensor's centroid: not on a boundary");
  for (bool mirror : {false, true})
    for (int k = 0; k < L; ++k) {
      const auto map = candidate(l, k, mirror, group.tolerance);
      if (!map) continue;
      const auto perm = electrode_permutation(l, *map, group.tolerance);
      if (!perm || boundary_mismatch(l, *map, group.tolerance)) continue;
      if (const auto g = index_element(*perm, mirror)) group.elements.push_back({*g, *map, *perm});
    }
  // The identity always passes (k = 0 maps every point onto itself); order by angle after it.
  std::stable_sort(group.elements.begin(), group.elements.end(), [](const auto& a, const auto& b) {
    if (a.map.is_reflection() != b.map.is_reflection()) return !a.map.is_reflection();
    return turn_of(a.map) < turn_of(b.map) - 1e-9;
  });
  return group;
}

void require_sensor_symmetries(const std::vector<GroupElement>& elements, const Mesh& mesh,
                               const SensorGroup& group, const std::string& source) {
  const int L = group.electrodes;
  for (const GroupElement& g : elements) {
    if (group.find(g)) continue;
    const std::string head = fmt::format(
        "{} is not a symmetry of this sensor (its group: {}, {} "
        "element{})",
        g.to_string(), group.name(), group.order(), group.order() == 1 ? "" : "s");
    const Layout l = measure(mesh);
    const int target = electrode_image(g, 0, L);
    const auto map = candidate(l, target, g.mirror, group.tolerance);
    if (!map)
      throw InputError(source, "electrode_" + std::to_string(target),
                       head + fmt::format(": electrode {} is at another distance from the "
                                          "centroid than electrode 0",
                                          target));
    for (int e = 0; e < L; ++e) {
      const int j = electrode_image(g, e, L);
      if (const auto why = electrode_mismatch(l, *map, e, j, group.tolerance))
        throw InputError(
            source, "electrode_" + std::to_string(e),
            head +
                fmt::format(": moved so that electrode 0's centre lands on electrode {}'s, ",
                            target) +
                (e == 0 ? "electrode 0 itself does not: "
                        : fmt::format("electrode {} should land on electrode {}, but ", e, j)) +
                *why);
    }
    const auto why = boundary_mismatch(l, *map, group.tolerance);
    throw InputError(source, "boundary",
                     head + ": the electrodes match, but " + why.value_or("the boundary differs"));
  }
}

}  // namespace eitbench
