// ShapeMeshOptions and the perimeter walk the shape mesher puts electrodes on; a build without Gmsh
// meshes only the symmetric disk (from files).
#include <algorithm>
#include <cmath>
#include <vector>

#include "eitbench/jacobian/constants.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/shape_mesh.h"

namespace eitbench {
namespace {

[[noreturn]] void fail(const char* field, const std::string& why) {
  throw InputError("ShapeMeshOptions", field, why);
}

// The ellipse's parametric angle at each of n + 1 equal steps of arc length over a quarter.
std::vector<double> quarter_table(double a, double b, int n) {
  const int fine = 64 * n;
  std::vector<double> length(fine + 1, 0.0);
  auto speed = [&](double t) { return std::hypot(a * std::sin(t), b * std::cos(t)); };
  const double dt = 0.5 * kPi / fine;
  for (int i = 0; i < fine; ++i)  // Simpson on each step
    length[i + 1] =
        length[i] + dt / 6 * (speed(i * dt) + 4 * speed((i + 0.5) * dt) + speed((i + 1) * dt));
  std::vector<double> t(n + 1);
  for (int k = 0; k <= n; ++k) {
    const double target = length[fine] * k / n;
    const auto it = std::lower_bound(length.begin(), length.end(), target);
    const int i = std::clamp(static_cast<int>(it - length.begin()), 1, fine);
    const double f = (target - length[i - 1]) / (length[i] - length[i - 1]);
    t[k] = (i - 1 + f) * dt;
  }
  return t;
}

}  // namespace

SensorShape parse_shape(const std::string& name) {
  if (name == "disk") return SensorShape::disk;
  if (name == "rectangle") return SensorShape::rectangle;
  if (name == "ellipse") return SensorShape::ellipse;
  throw InputError("SensorShape", "name",
                   "unknown shape '" + name + "' (disk, rectangle or ellipse)");
}

std::string to_string(SensorShape shape) {
  switch (shape) {
    case SensorShape::disk:
      return "disk";
    case SensorShape::rectangle:
      return "rectangle";
    case SensorShape::ellipse:
      return "ellipse";
  }
  return "?";
}

void ShapeMeshOptions::validate() const {
  if (electrodes < 4 || electrodes > 256)
    fail("electrodes", "need 4 <= L <= 256, got " + std::to_string(electrodes));
  for (double side : {width, height})
    if (!(side > 0) || !std::isfinite(side)) fail("width", "width and height must be positive");
  if (std::max(width, height) > 20 * std::min(width, height))
    fail("height", "the sides' ratio must be at most 20");
  if (shape == SensorShape::disk && width != height)
    fail("height", "a disk's width and height are its diameter: use ellipse for unequal axes");
  if (!(electrode_coverage > 0 && electrode_coverage < 1))
    fail("electrode_coverage", "must lie strictly between 0 and 1");
  if (!(size_factor >= 0.1 && size_factor <= 10)) fail("size_factor", "must lie in [0.1, 10]");
  if (electrode_positions.empty()) return;
  const int L = static_cast<int>(electrode_positions.size());
  if (L != electrodes)
    fail("electrode_positions", "has " + std::to_string(L) + " positions for " +
                                    std::to_string(electrodes) + " electrodes");
  const double w = electrode_coverage / L;
  for (int e = 0; e < L; ++e) {
    const double p = electrode_positions[e];
    if (!(p >= 0 && p < 1))
      fail("electrode_positions", "position " + std::to_string(e) + " is outside [0, 1)");
    const double next = e + 1 < L ? electrode_positions[e + 1] : electrode_positions[0] + 1;
    if (!(next - p > w))
      fail("electrode_positions", "electrodes " + std::to_string(e) + " and " +
                                      std::to_string((e + 1) % L) +
                                      " overlap or are out of order (each spans " +
                                      std::to_string(w) + " of the perimeter)");
  }
}

PerimeterPoint perimeter_point(const ShapeMeshOptions& o, double s) {
  s -= std::floor(s);
  const double a = 0.5 * o.width, b = 0.5 * o.height;
  if (o.shape == SensorShape::rectangle) {
    double d = s * 4 * (a + b);  // walked from (a, 0): up b, left 2a, down 2b, right 2a, up b
    if (d <= b) return {a, d};
    if ((d -= b) <= 2 * a) return {a - d, b};
    if ((d -= 2 * a) <= 2 * b) return {-a, b - d};
    if ((d -= 2 * b) <= 2 * a) return {-a + d, -b};
    return {a, -b + (d - 2 * a)};
  }
  // An ellipse by arc length, one quarter tabulated and mirrored (exactly symmetric).
  constexpr int kSteps = 4096;
  static thread_local double table_a = -1, table_b = -1;
  static thread_local std::vector<double> table;
  if (a != table_a || b != table_b) {
    table = quarter_table(a, b, kSteps);
    table_a = a;
    table_b = b;
  }
  const int quarter = std::min(static_cast<int>(s * 4), 3);
  double q = s * 4 - quarter;  // within the quarter, 0 .. 1
  if (quarter % 2 == 1) q = 1 - q;
  const double x = q * kSteps;
  const int i = std::min(static_cast<int>(x), kSteps - 1);
  const double t = table[i] + (x - i) * (table[i + 1] - table[i]);
  const double px = a * std::cos(t), py = b * std::sin(t);
  return {quarter == 0 || quarter == 3 ? px : -px, quarter < 2 ? py : -py};
}

#ifndef EITBENCH_HAVE_GMSH
Mesh generate_shape_mesh(const ShapeMeshOptions& o) {
  o.validate();
  if (o.shape == SensorShape::disk && o.electrode_positions.empty())
    return generate_disk_mesh(
        {o.electrodes, o.density, 0.5 * o.width, o.electrode_coverage, o.size_factor});
  throw InputError("--shape", "",
                   "this build has no Gmsh to mesh a " + to_string(o.shape) +
                       ": write it with `eitbench mesh --shape ... --out FILE` on a build with "
                       "Gmsh and pass --mesh FILE");
}
#endif

}  // namespace eitbench
