#include "eitbench/jacobian/electrode_shift.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

constexpr double kTwoPi = 2 * M_PI;
const char* const kFlag = "--randomise-electrodes";

std::vector<int> electrode_nodes(const Electrode& el) {
  if (el.is_point()) return {el.point_node};
  std::vector<int> nodes;
  for (const auto& s : el.segments) nodes.insert(nodes.end(), {s[0], s[1]});
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

double node_angle(const Mesh& mesh, int n) {
  return std::atan2(mesh.nodes(n, 1), mesh.nodes(n, 0));
}

// An angle in [0, 2 pi).
double turn_of(double a) {
  a = std::fmod(a, kTwoPi);
  return a < 0 ? a + kTwoPi : a;
}

// An electrode's stretch of rim, counter-clockwise from `start` over `width`, and the gap to the
// next electrode counter-clockwise.
struct Arc {
  int electrode;
  double start, width, gap;
};

std::vector<Arc> electrode_arcs(const Mesh& disk) {
  std::vector<Arc> arcs;
  for (int e = 0; e < disk.num_electrodes(); ++e) {
    const double centre = electrode_angle(disk, e);
    double lo = 0, hi = 0;
    for (int n : electrode_nodes(disk.electrodes[e])) {
      const double d = std::remainder(node_angle(disk, n) - centre, kTwoPi);
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
    arcs.push_back({e, turn_of(centre + lo), hi - lo, 0});
  }
  std::sort(arcs.begin(), arcs.end(), [](const Arc& a, const Arc& b) { return a.start < b.start; });
  for (std::size_t k = 0; k < arcs.size(); ++k) {
    const Arc& next = arcs[(k + 1) % arcs.size()];
    arcs[k].gap = turn_of(next.start - arcs[k].start) - arcs[k].width;
    if (arcs.size() == 1) arcs[k].gap = kTwoPi - arcs[k].width;
  }
  return arcs;
}

// The rim's turn at angle theta: an electrode's own shift on its arc, linear across a gap.
double rim_turn(const std::vector<Arc>& arcs, const std::vector<double>& shifts, double theta) {
  for (std::size_t k = 0; k < arcs.size(); ++k) {
    const Arc& a = arcs[k];
    const double d = turn_of(theta - a.start);
    if (d <= a.width) return shifts[a.electrode];
    if (d <= a.width + a.gap) {
      const double t = (d - a.width) / a.gap;
      return (1 - t) * shifts[a.electrode] + t * shifts[arcs[(k + 1) % arcs.size()].electrode];
    }
  }
  return 0;  // not reached: the arcs and gaps cover the circle
}

}  // namespace

double electrode_angle(const Mesh& disk, int e) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  const std::vector<int> nodes = electrode_nodes(disk.electrodes.at(e));
  for (int n : nodes) mean += disk.nodes.row(n).transpose();
  return std::atan2(mean.y(), mean.x());
}

double max_neighbour_shift(const Mesh& disk) {
  double narrowest = kTwoPi;
  for (const Arc& a : electrode_arcs(disk)) narrowest = std::min(narrowest, a.gap);
  return narrowest / 2;
}

Mesh shift_electrodes(const Mesh& disk, const std::vector<double>& shifts) {
  if (static_cast<int>(shifts.size()) != disk.num_electrodes())
    throw InputError(kFlag, "",
                     std::to_string(shifts.size()) + " shifts for " +
                         std::to_string(disk.num_electrodes()) + " electrodes");
  const std::vector<Arc> arcs = electrode_arcs(disk);
  const double limit = max_neighbour_shift(disk);
  for (std::size_t k = 0; k < arcs.size(); ++k) {
    const double step = shifts[arcs[(k + 1) % arcs.size()].electrode] - shifts[arcs[k].electrode];
    if (!(std::abs(step) <= limit))
      throw InputError(kFlag, "",
                       "neighbouring electrodes' shifts differ by more than half their gap");
  }
  const double R = disk.nodes.rowwise().norm().maxCoeff();
  Mesh out = disk;
  for (int n = 0; n < disk.num_nodes(); ++n) {
    const double rho = disk.nodes.row(n).norm();
    if (rho == 0) continue;
    const double theta = node_angle(disk, n);
    const double turn = (rho / R) * (rho / R) * rim_turn(arcs, shifts, theta);
    if (turn == 0) continue;  // exactly where it was
    const double turned = theta + turn;
    out.nodes(n, 0) = rho * std::cos(turned);
    out.nodes(n, 1) = rho * std::sin(turned);
  }
  if (!(triangle_areas(out).array() > 0).all())
    throw InputError(kFlag, "", "the shifts would turn a triangle over: use smaller shifts");
  return out;
}

}  // namespace eitbench
