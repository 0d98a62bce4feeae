#include "eitbench/bench/ktc/tank_simulation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "eitbench/jacobian/constants.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

// The largest radius * shape(t) over t: what keeps targets apart and inside the tank.
double reach(const KtcTarget& t) {
  double sum = 1;
  for (double a : t.harmonics) sum += std::abs(a);
  return t.radius * sum;
}

KtcTarget draw_target(std::mt19937_64& rng, const KtcSimulationOptions& o, double R) {
  std::uniform_real_distribution<double> u(0, 1);
  KtcTarget t;
  t.radius = R * (o.smallest + (o.largest - o.smallest) * u(rng));
  t.cls = u(rng) < 0.5 ? 1 : 2;
  t.phase = 2 * kPi * u(rng);
  const double shape = u(rng);
  if (shape < 1.0 / 3) {
    t.corners = 3 + static_cast<int>(4 * u(rng));  // 3 ... 6 corners
  } else if (shape < 2.0 / 3) {
    for (int k = 2; k <= 4; ++k)  // rounded blobs: harmonics 2-4, smaller as they rise
      for (int part = 0; part < 2; ++part) t.harmonics.push_back((0.3 / k) * (2 * u(rng) - 1));
  }
  const double r = 0.9 * R - reach(t);
  const double rho = r * std::sqrt(u(rng)), angle = 2 * kPi * u(rng);  // uniform in the disc
  t.centre = {rho * std::cos(angle), rho * std::sin(angle)};
  if (o.contrast_spread > 1)  // drawn last: a set without a spread keeps its numbers
    t.contrast =
        (t.cls == 1 ? o.resistive : o.conductive) * std::pow(o.contrast_spread, 2 * u(rng) - 1);
  return t;
}

}  // namespace

double KtcTarget::boundary(double angle) const {
  if (corners >= 3) {  // a regular polygon of circumradius `radius`
    const double sector = 2 * kPi / corners;
    const double a = std::fmod(std::fmod(angle - phase, sector) + sector, sector) - sector / 2;
    return radius * std::cos(kPi / corners) / std::cos(a);
  }
  double shape = 1;
  for (std::size_t i = 0; i + 1 < harmonics.size(); i += 2) {
    const double k = 2 + static_cast<double>(i / 2);
    shape += harmonics[i] * std::cos(k * (angle - phase)) +
             harmonics[i + 1] * std::sin(k * (angle - phase));
  }
  return radius * shape;
}

bool KtcTarget::contains(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d d = point - centre;
  return d.norm() < boundary(std::atan2(d.y(), d.x()));
}

void KtcSimulationOptions::validate() const {
  const auto fail = [](const std::string& field, const std::string& message) {
    throw InputError("KtcSimulationOptions", field, message);
  };
  if (samples < 1) fail("samples", "must be at least 1");
  if (max_targets < 1 || max_targets > 8) fail("max_targets", "must be 1 ... 8");
  if (!(smallest > 0) || !(largest >= smallest) || !(largest <= 0.45))
    fail("largest", "target radii need 0 < smallest <= largest <= 0.45 of the tank's");
  if (!(resistive > 0 && resistive < 1)) fail("resistive", "must lie in (0, 1)");
  if (!(conductive > 1) || !std::isfinite(conductive)) fail("conductive", "must exceed 1");
  if (!(contrast_spread >= 1) || !(resistive * contrast_spread < 1) ||
      !(conductive / contrast_spread > 1))
    fail("contrast_spread",
         "must be at least 1 and keep resistive targets below the background, conductive above");
  if (!(noise >= 0) || !std::isfinite(noise)) fail("noise", "must be finite and >= 0");
  if (grid < 8 || grid > 1024) fail("grid", "must be 8 ... 1024");
}

std::vector<KtcTarget> draw_ktc_targets(std::mt19937_64& rng, const KtcSimulationOptions& o,
                                        double R) {
  const int count = std::uniform_int_distribution<int>(1, o.max_targets)(rng);
  std::vector<KtcTarget> targets;
  // Rejection: a target that meets one placed before is drawn again (a few hundred tries at most;
  // a tank that cannot hold them all keeps those it has).
  for (int tries = 0; static_cast<int>(targets.size()) < count && tries < 500; ++tries) {
    const KtcTarget t = draw_target(rng, o, R);
    const bool apart = std::all_of(targets.begin(), targets.end(), [&](const KtcTarget& s) {
      return (t.centre - s.centre).norm() > reach(t) + reach(s) + 0.05 * R;
    });
    if (apart) targets.push_back(t);
  }
  return targets;
}

Eigen::VectorXd ktc_conductivity(const Mesh& mesh, double background,
                                 const std::vector<KtcTarget>& targets,
                                 const KtcSimulationOptions& o) {
  Eigen::VectorXd sigma = Eigen::VectorXd::Constant(mesh.num_triangles(), background);
  for (int e = 0; e < mesh.num_triangles(); ++e) {
    const Eigen::Vector2d c = triangle_centroid(mesh, e);
    for (const KtcTarget& t : targets)
      if (t.contains(c))
        sigma[e] = background * (t.contrast > 0 ? t.contrast
                                 : t.cls == 1   ? o.resistive
                                                : o.conductive);
  }
  return sigma;
}

ClassImage ktc_labels(const std::vector<KtcTarget>& targets, double R,
                      const KtcSimulationOptions& o) {
  ClassImage labels = ClassImage::Zero(o.grid, o.grid);
  const double w = 2 * R / o.grid;
  for (int i = 0; i < o.grid; ++i)
    for (int j = 0; j < o.grid; ++j) {
      const Eigen::Vector2d p = o.orientation.to_model({-R + (j + 0.5) * w, R - (i + 0.5) * w});
      for (const KtcTarget& t : targets)
        if (t.contains(p)) labels(i, j) = static_cast<std::uint8_t>(t.cls);
    }
  return labels;
}

KtcSimulatedSet simulate_ktc_tanks(const KtcTank& tank, const KtcSimulationOptions& o) {
  o.validate();
  const double R = tank.options.radius;
  KtcSimulatedSet set;
  std::mt19937_64 rng(o.seed);
  for (int n = 0; n < o.samples; ++n) set.targets.push_back(draw_ktc_targets(rng, o, R));
  const Eigen::VectorXd empty =
      tank.model->measured(Eigen::VectorXd::Constant(tank.mesh.num_triangles(), tank.background));
  set.frames.resize(o.samples, empty.size());
  set.labels.resize(o.samples);
  // Each sample from its targets and its own noise stream: the same on any thread count.
  tbb::parallel_for(0, o.samples, [&](int n) {
    const auto& targets = set.targets[n];
    Eigen::VectorXd frame =
        tank.model->measured(ktc_conductivity(tank.mesh, tank.background, targets, o)) - empty;
    std::mt19937_64 noise_rng(o.seed * 1000003ULL + static_cast<unsigned long long>(n));
    std::normal_distribution<double> noise(0, 1);
    if (o.noise > 0)
      for (auto& v : frame) v += o.noise * noise(noise_rng);
    set.frames.row(n) = frame.transpose();
    set.labels[n] = ktc_labels(targets, R, o);
  });
  return set;
}

double repeated_pattern_noise(const Eigen::VectorXd& frame, const CurrentPatterns& p) {
  const int M = p.differences();
  if (frame.size() != static_cast<Eigen::Index>(p.size()))
    throw InputError(
        "frame", "values",
        "has " + std::to_string(frame.size()) + " values, not " + std::to_string(p.size()));
  double squares = 0;
  long long count = 0;
  for (int j = 0; j < p.patterns(); ++j)
    for (int k = j + 1; k < p.patterns(); ++k) {
      const Eigen::VectorXd a = p.injection.col(j), b = p.injection.col(k);
      const double s = a.dot(b) / a.squaredNorm();  // b = s a for a repeated pattern
      // The same currents again only: a reversed pair's frame differs by twice each difference's
      // offset as well (KTC's about 0.02 V, which a difference frame cancels), not by noise.
      if (s <= 0 || (b - s * a).norm() > 1e-9 * b.norm()) continue;
      const Eigen::VectorXd d = frame.segment(k * M, M) - s * frame.segment(j * M, M);
      for (double v : d)
        if (std::isfinite(v)) squares += v * v / (1 + s * s), ++count;
    }
  if (count == 0)
    throw InputError(
        "frame", "patterns",
        "no pattern is driven twice in the same direction: the noise is not measurable");
  return std::sqrt(squares / static_cast<double>(count));
}

}  // namespace eitbench
