#pragma once
// KTC2023's tank (docs/ktc.md#the-tank): a disk of radius 115 mm with 32 electrodes, its protocol
// the reference measurement's current patterns, its background conductivity and contact
// impedances calibrated to the empty tank's frame, and the challenge's difficulty levels.
#include <memory>
#include <string>
#include <vector>

#include "eitbench/bench/ktc/ktc_files.h"
#include "eitbench/jacobian/disk_mesh.h"
#include "eitbench/jacobian/forward_model.h"

namespace eitbench {

struct KtcTankOptions {
  double radius = 0.115;  // m, the tank's (KTC: 230 mm across)
  // The perimeter's share under electrodes. The default is the empty tank's best fit among
  // 0.3 ... 0.7 (docs/ktc.md#the-tank).
  double electrode_coverage = 0.5;
  MeshDensity density = MeshDensity::medium;
  double size_factor = 1.0;  // DiskMeshOptions::size_factor
  // Where the calibration starts: sigma_0 (S/m, of the 2-D model) and every contact impedance.
  double background_start = 1.0, contact_start = 1e-3;

  // InputError("KtcTankOptions", field) for a value out of range.
  void validate() const;
  DiskMeshOptions mesh_options() const;
};

struct KtcTank {
  KtcTankOptions options;
  Mesh mesh;
  std::shared_ptr<const MeasurementProtocol> protocol;  // the reference's Inj and Mpat
  double background = 0;                                // calibrated sigma_0
  Eigen::VectorXd contact_impedances;                   // calibrated, one an electrode
  double relative_residual = 0;  // ||model - reference|| / ||reference|| at the calibration
  std::shared_ptr<const ForwardModel> model;  // at the calibrated impedances
  Eigen::VectorXd reference;                  // the empty tank's frame (Uelref)
};

// Meshes the tank and calibrates it to `reference` (the empty tank: ref.mat).
KtcTank calibrate_ktc_tank(const KtcMeasurement& reference, const KtcTankOptions& options = {});
// The tank at a calibration made before (a run's): no fit. InputError("calibration", field) for
// a background or impedances that are not positive and finite, or not one impedance an electrode.
KtcTank ktc_tank_at(const KtcMeasurement& reference, const KtcTankOptions& options,
                    double background, const Eigen::VectorXd& contact_impedances);

// The electrodes KTC's difficulty level removes (0-based): 1 .. 2(level - 1) in KTC's numbering.
// InputError("level", "") for a level outside 1 ... 7.
std::vector<int> ktc_removed_electrodes(int level);
// A frame (a measurement's voltages) with the values of `level` missing (NaN): every value whose
// pattern drives, or whose difference reads, a removed electrode.
Eigen::VectorXd ktc_level_frame(const Eigen::VectorXd& voltages, const CurrentPatterns& patterns,
                                int level);

// The measurement's patterns against the reference's (the tank's): InputError(measurement.path,
// field) when they differ (a measurement of another protocol cannot be reconstructed on this
// tank's model).
void check_same_patterns(const KtcMeasurement& measurement, const CurrentPatterns& reference);

}  // namespace eitbench
