#include "eitbench/bench/ktc/tank.h"

#include <cmath>

#include "eitbench/jacobian/error.h"
#include "eitbench/solvers/calibration.h"

namespace eitbench {

void KtcTankOptions::validate() const {
  auto positive = [](double v) { return v > 0 && std::isfinite(v); };
  if (!positive(radius))
    throw InputError("KtcTankOptions", "radius", "must be positive and finite");
  if (!(electrode_coverage > 0 && electrode_coverage < 1))
    throw InputError("KtcTankOptions", "electrode_coverage", "must lie strictly between 0 and 1");
  if (!positive(background_start))
    throw InputError("KtcTankOptions", "background_start", "must be positive and finite");
  if (!positive(contact_start))
    throw InputError("KtcTankOptions", "contact_start", "must be positive and finite");
  mesh_options().validate();
}

DiskMeshOptions KtcTankOptions::mesh_options() const {
  DiskMeshOptions o;
  o.electrodes = 32;
  o.density = density;
  o.radius = radius;
  o.electrode_coverage = electrode_coverage;
  o.size_factor = size_factor;
  return o;
}

namespace {

// The tank's mesh and protocol, not yet calibrated.
KtcTank uncalibrated(const KtcMeasurement& reference, const KtcTankOptions& options) {
  options.validate();
  if (reference.patterns.electrodes() != 32)
    throw InputError(reference.path, "Injref",
                     "has " + std::to_string(reference.patterns.electrodes()) +
                         " electrodes; KTC's tank has 32");
  KtcTank tank;
  tank.options = options;
  tank.mesh = generate_disk_mesh(options.mesh_options());
  tank.protocol =
      std::make_shared<const MeasurementProtocol>("ktc", reference.patterns, reference.path);
  tank.reference = reference.voltages;
  return tank;
}

}  // namespace

KtcTank ktc_tank_at(const KtcMeasurement& reference, const KtcTankOptions& options,
                    double background, const Eigen::VectorXd& contact_impedances) {
  KtcTank tank = uncalibrated(reference, options);
  if (!(background > 0) || !std::isfinite(background))
    throw InputError("calibration", "background", "must be positive and finite");
  if (contact_impedances.size() != 32 || !contact_impedances.allFinite() ||
      !(contact_impedances.minCoeff() > 0))
    throw InputError("calibration", "contact_impedances", "must be 32 positive, finite values");
  ForwardOptions forward;
  forward.protocol = tank.protocol;
  forward.contact_impedances = contact_impedances;
  tank.background = background;
  tank.contact_impedances = contact_impedances;
  tank.model = std::make_shared<const ForwardModel>(tank.mesh, forward);
  const Eigen::VectorXd v =
      tank.model->measured(Eigen::VectorXd::Constant(tank.mesh.num_triangles(), background));
  double misfit = 0, norm = 0;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (std::isfinite(tank.reference[i]))
      misfit += std::pow(v[i] - tank.reference[i], 2), norm += std::pow(tank.reference[i], 2);
  if (!(norm > 0)) throw InputError(reference.path, "Uelref", "has no finite value but zeros");
  tank.relative_residual = std::sqrt(misfit / norm);
  return tank;
}

KtcTank calibrate_ktc_tank(const KtcMeasurement& reference, const KtcTankOptions& options) {
  KtcTank tank = uncalibrated(reference, options);
  ForwardOptions forward;
  forward.protocol = tank.protocol;
  forward.contact_impedance = options.contact_start;
#ifdef EITBENCH_HAVE_CERES
  const Calibration c = calibrate_measured(tank.mesh, forward, options.background_start,
                                           reference.voltages, {}, reference.path);
  tank.background = c.background;
  tank.contact_impedances = c.contact_impedances;
  tank.relative_residual = c.relative_residual;
  forward.contact_impedances = c.contact_impedances;
  tank.model = std::make_shared<const ForwardModel>(tank.mesh, forward);
#else
  throw InputError(reference.path, "", "calibrating the tank needs a build with Ceres");
#endif
  return tank;
}

std::vector<int> ktc_removed_electrodes(int level) {
  if (level < 1 || level > 7)
    throw InputError("level", "", std::to_string(level) + " is not a KTC level (1 ... 7)");
  std::vector<int> out;
  for (int e = 0; e < 2 * (level - 1); ++e) out.push_back(e);
  return out;
}

Eigen::VectorXd ktc_level_frame(const Eigen::VectorXd& voltages, const CurrentPatterns& patterns,
                                int level) {
  const std::vector<bool> keep = patterns.values_without(ktc_removed_electrodes(level));
  if (voltages.size() != patterns.size())
    throw std::invalid_argument("ktc_level_frame: one voltage a pattern and difference");
  Eigen::VectorXd out = voltages;
  for (Eigen::Index i = 0; i < out.size(); ++i)
    if (!keep[static_cast<std::size_t>(i)]) out[i] = std::nan("");
  return out;
}

void check_same_patterns(const KtcMeasurement& measurement, const CurrentPatterns& p) {
  const CurrentPatterns& q = measurement.patterns;
  if (q.electrodes() != p.electrodes() || q.patterns() != p.patterns() ||
      q.differences() != p.differences())
    throw InputError(
        measurement.path, "Inj",
        "has another shape of patterns than the reference's: " + std::to_string(q.patterns()) +
            " patterns x " + std::to_string(q.differences()) + " differences, the reference " +
            std::to_string(p.patterns()) + " x " + std::to_string(p.differences()));
  if (q.measurement != p.measurement)
    throw InputError(measurement.path, "Mpat", "differs from the reference's Mpat");
  const double scale = p.injection.cwiseAbs().maxCoeff();
  if ((q.injection - p.injection).cwiseAbs().maxCoeff() > 1e-9 * scale)
    throw InputError(measurement.path, "Inj", "differs from the reference's Injref");
}

}  // namespace eitbench
