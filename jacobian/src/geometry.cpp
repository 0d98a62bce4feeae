#include "eitbench/jacobian/geometry.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

double cross(const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
  return p.x() * q.y() - p.y() * q.x();
}

// Signed area of (disk of radius r at the origin) intersected with triangle (origin, a, b): the
// segment a-b is cut where it crosses the circle; straight pieces inside contribute a triangle,
// arcs outside a circular sector.
double origin_wedge_overlap(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double r) {
  const Eigen::Vector2d d = b - a;
  const double qa = d.dot(d);
  if (qa == 0) return 0;
  const double qb = a.dot(d), qc = a.dot(a) - r * r;
  double t[4] = {0, 0, 0, 1};
  int n = 1;
  const double disc = qb * qb - qa * qc;
  if (disc > 0) {
    const double s = std::sqrt(disc);
    for (double root : {(-qb - s) / qa, (-qb + s) / qa})
      if (root > 0 && root < 1) t[n++] = root;
  }
  t[n++] = 1;
  double sum = 0;
  for (int i = 0; i + 1 < n; ++i) {
    const Eigen::Vector2d p = a + t[i] * d, q = a + t[i + 1] * d;
    const Eigen::Vector2d mid = a + 0.5 * (t[i] + t[i + 1]) * d;
    if (mid.squaredNorm() <= r * r)
      sum += 0.5 * cross(p, q);
    else
      sum += 0.5 * r * r * std::atan2(cross(p, q), p.dot(q));
  }
  return sum;
}

}  // namespace

double triangle_circle_overlap(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                               const Eigen::Vector2d& c, const Eigen::Vector2d& center, double r) {
  if (!(r > 0)) return 0;
  const Eigen::Vector2d p[3] = {a - center, b - center, c - center};
  double sum = 0;
  for (int k = 0; k < 3; ++k) sum += origin_wedge_overlap(p[k], p[(k + 1) % 3], r);
  return std::abs(sum);
}

double triangle_box_overlap(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                            const Eigen::Vector2d& c, double x0, double x1, double y0, double y1) {
  // Sutherland-Hodgman: clip the triangle against the box's four half-planes in turn.
  std::vector<Eigen::Vector2d> poly{a, b, c}, next;
  auto clip = [&](int axis, double bound, bool keep_below) {
    next.clear();
    auto inside = [&](const Eigen::Vector2d& p) {
      return keep_below ? p[axis] <= bound : p[axis] >= bound;
    };
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Eigen::Vector2d& p = poly[i];
      const Eigen::Vector2d& q = poly[(i + 1) % poly.size()];
      if (inside(p)) next.push_back(p);
      if (inside(p) != inside(q)) {
        const double s = (bound - p[axis]) / (q[axis] - p[axis]);
        next.push_back(p + s * (q - p));
      }
    }
    poly.swap(next);
  };
  clip(0, x0, false);
  if (!poly.empty()) clip(0, x1, true);
  if (!poly.empty()) clip(1, y0, false);
  if (!poly.empty()) clip(1, y1, true);
  double area = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) area += cross(poly[i], poly[(i + 1) % poly.size()]);
  return std::abs(0.5 * area);
}

bool point_in_triangle(const Eigen::Vector2d& x, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                       const Eigen::Vector2d& c) {
  // Inside (or on an edge) when x is on no two sides' opposite sides.
  const double d1 = cross(b - a, x - a), d2 = cross(c - b, x - b), d3 = cross(a - c, x - c);
  const bool some_negative = std::min({d1, d2, d3}) < 0;
  const bool some_positive = std::max({d1, d2, d3}) > 0;
  return !(some_negative && some_positive);
}

MeshDomain::MeshDomain(const Mesh& mesh) {
  for (const auto& [i, j] : boundary_edges(mesh))
    segments_.emplace_back(mesh.nodes.row(i).transpose(), mesh.nodes.row(j).transpose());
}

bool MeshDomain::contains(const Eigen::Vector2d& x) const {
  bool inside = false;
  for (const auto& [a, b] : segments_)
    if ((a.y() > x.y()) != (b.y() > x.y()) &&
        x.x() < a.x() + (x.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
      inside = !inside;
  return inside;
}

double MeshDomain::boundary_distance(const Eigen::Vector2d& x) const {
  double best = INFINITY;
  for (const auto& [a, b] : segments_) {
    const Eigen::Vector2d ab = b - a;
    const double t = std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * ab - x).norm());
  }
  return best;
}

Eigen::VectorXd conductivity_from_circles(const Mesh& mesh, const std::vector<Circle>& circles,
                                          double background) {
  Eigen::VectorXd sigma = Eigen::VectorXd::Constant(mesh.num_triangles(), background);
  const Eigen::VectorXd area = triangle_areas(mesh);
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector2d a = mesh.nodes.row(mesh.triangles(t, 0)),
                          b = mesh.nodes.row(mesh.triangles(t, 1)),
                          c = mesh.nodes.row(mesh.triangles(t, 2));
    const Eigen::Vector2d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    for (const Circle& circle : circles) {
      if (circle.x + circle.r < lo.x() || circle.x - circle.r > hi.x() ||
          circle.y + circle.r < lo.y() || circle.y - circle.r > hi.y())
        continue;
      const double overlap = triangle_circle_overlap(a, b, c, {circle.x, circle.y}, circle.r);
      sigma[t] += (circle.conductivity - background) * overlap / std::abs(area[t]);
    }
  }
  return sigma;
}

std::vector<Circle> parse_circles(const std::string& text, const std::string& source) {
  std::vector<Circle> circles;
  std::stringstream all(text);
  std::string item;
  int index = 0;
  while (std::getline(all, item, ';')) {
    if (item.find_first_not_of(" \t") == std::string::npos) continue;
    const std::string field = "circle " + std::to_string(index++);
    std::stringstream parts(item);
    std::string part;
    double v[4];
    int n = 0;
    while (std::getline(parts, part, ',')) {
      if (n == 4) throw InputError(source, field, "has more than 4 values (x,y,r,s)");
      errno = 0;
      char* end = nullptr;
      v[n] = std::strtod(part.c_str(), &end);
      while (end && (*end == ' ' || *end == '\t')) ++end;
      if (end == part.c_str() || (end && *end != '\0') || errno == ERANGE)
        throw InputError(source, field, "'" + part + "' is not a number");
      if (!std::isfinite(v[n])) throw InputError(source, field, "values must be finite");
      ++n;
    }
    if (n != 4)
      throw InputError(source, field, "needs 4 values x,y,r,s, found " + std::to_string(n));
    if (!(v[2] > 0)) throw InputError(source, field, "the radius must be positive");
    if (!(v[3] > 0)) throw InputError(source, field, "the conductivity must be positive");
    circles.push_back({v[0], v[1], v[2], v[3]});
  }
  if (circles.empty()) throw InputError(source, "", "no circle given (expected \"x,y,r,s;...\")");
  return circles;
}

}  // namespace eitbench
