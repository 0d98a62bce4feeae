#pragma once
// Exact planar geometry the physics needs: triangle-circle and triangle-rectangle overlap areas.
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "eitbench/jacobian/mesh.h"

namespace eitbench {

struct Circle {
  double x = 0, y = 0, r = 0;
  double conductivity = 0;  // S/m inside the circle
};

// Area of triangle (a, b, c) intersected with the disk of centre `center` and radius r (exact).
double triangle_circle_overlap(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                               const Eigen::Vector2d& c, const Eigen::Vector2d& center, double r);
// Area of triangle (a, b, c) intersected with the box [x0, x1] x [y0, y1] (exact, by clipping).
double triangle_box_overlap(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                            const Eigen::Vector2d& c, double x0, double x1, double y0, double y1);

// Whether x lies in triangle (a, b, c) of either orientation, its edges included.
bool point_in_triangle(const Eigen::Vector2d& x, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                       const Eigen::Vector2d& c);

// A mesh's domain as point queries need it: its boundary (the edges of one triangle only), found
// once, so that each query costs one pass over the boundary's segments.
class MeshDomain {
 public:
  explicit MeshDomain(const Mesh& mesh);
  // Inside by the even-odd rule over the boundary (holes excluded); a point on the boundary may
  // count either way.
  bool contains(const Eigen::Vector2d& x) const;
  // The distance from x to the boundary: a circle of radius r about a point inside lies inside
  // the domain when r <= this distance.
  double boundary_distance(const Eigen::Vector2d& x) const;

 private:
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> segments_;
};

// Element conductivities of non-overlapping circles on a background: each triangle gets the
// area-weighted mean, from exact circle-triangle overlaps.
Eigen::VectorXd conductivity_from_circles(const Mesh& mesh, const std::vector<Circle>& circles,
                                          double background);

// Parses "x,y,r,s;x,y,r,s;..." (throws InputError naming `source`, e.g. "--circles").
std::vector<Circle> parse_circles(const std::string& text, const std::string& source);

}  // namespace eitbench
