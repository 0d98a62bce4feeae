#pragma once
// KTC2023's protocol built from its description (Inj: the 16 odd pairs, then electrodes 1, 9, 17
// and 25 each against the other odd ones; Mpat: the 31 adjacent differences), and a synthetic KTC
// folder made with it on the forward model: ref.mat, dataN.mat and trueN.mat as the challenge's
// files are laid out, for tests that must not need ../shared.
#include <Eigen/LU>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/matlab.h"
#include "eitbench/bench/ktc/score.h"
#include "eitbench/bench/ktc/segmentation.h"
#include "eitbench/bench/ktc/tank.h"
#include "eitbench/jacobian.h"

namespace eitbench::testing {

inline CurrentPatterns ktc_patterns(double amplitude = 1.5) {
  CurrentPatterns p;
  p.injection = Eigen::MatrixXd::Zero(32, 76);
  int k = 0;
  for (int e = 0; e < 32; e += 2, ++k)  // electrodes 1-3, 3-5, ..., 31-1 (0-based even)
    p.injection(e, k) = amplitude, p.injection((e + 2) % 32, k) = -amplitude;
  for (int e : {0, 8, 16, 24})
    for (int o = 0; o < 32; o += 2)
      if (o != e) p.injection(e, k) = -amplitude, p.injection(o, k) = amplitude, ++k;
  p.measurement = Eigen::MatrixXd::Zero(32, 31);
  for (int m = 0; m < 31; ++m) p.measurement(m, m) = 1, p.measurement(m + 1, m) = -1;
  return p;
}

// A tank of KTC's patterns on a coarse mesh at a uniform contact impedance, without calibration.
inline KtcTank ktc_coarse_tank() {
  KtcMeasurement reference;
  reference.path = "synthetic";
  reference.patterns = ktc_patterns();
  reference.voltages = Eigen::VectorXd::Ones(76 * 31);
  KtcTankOptions o;
  o.density = MeshDensity::coarse;
  return ktc_tank_at(reference, o, 0.8, Eigen::VectorXd::Constant(32, 5e-4));
}

inline detail::MatMatrix mat(const std::string& name, const Eigen::MatrixXd& m) {
  detail::MatMatrix out{
      name, static_cast<std::size_t>(m.rows()), static_cast<std::size_t>(m.cols()), {}, false};
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) out.values.push_back(m(i, j));
  return out;
}

// A disc of the image (KTC's coordinates, metres) with its class.
struct Target {
  double x, y, r;
  int cls;  // 1 resistive, 2 conductive
};

// Writes ref.mat and, for each target set, dataN.mat and trueN.mat (N from 1) into `dir`,
// simulated on the 32-electrode tank of radius 0.115 with electrode 1 where `orientation` puts it.
inline void write_synthetic_ktc(const std::filesystem::path& dir,
                                const std::vector<std::vector<Target>>& samples,
                                const KtcOrientation& orientation = {}) {
  std::filesystem::create_directories(dir);
  DiskMeshOptions mo;
  mo.electrodes = 32;
  mo.radius = 0.115;
  mo.density = MeshDensity::medium;
  const Mesh mesh = generate_disk_mesh(mo);
  const CurrentPatterns p = ktc_patterns();
  ForwardOptions fo;
  fo.contact_impedance = 5e-4;
  fo.protocol = std::make_shared<MeasurementProtocol>("ktc", p);
  const ForwardModel model(mesh, fo);
  const double sigma0 = 0.8;
  const Eigen::VectorXd ref =
      model.measured(Eigen::VectorXd::Constant(mesh.num_triangles(), sigma0));
  write_bytes_atomically((dir / "ref.mat").string(),
                         detail::mat_v5_bytes({mat("Injref", p.injection),
                                               mat("Mpat", p.measurement), mat("Uelref", ref)}));
  // Image point of a model point: the inverse of orientation.to_model (a rotation, maybe mirrored).
  const Eigen::Vector2d ex = orientation.to_model({1, 0}), ey = orientation.to_model({0, 1});
  Eigen::Matrix2d to_model;
  to_model << ex, ey;
  const Eigen::Matrix2d to_image = to_model.inverse();
  for (std::size_t n = 0; n < samples.size(); ++n) {
    Eigen::VectorXd sigma = Eigen::VectorXd::Constant(mesh.num_triangles(), sigma0);
    for (int t = 0; t < mesh.num_triangles(); ++t) {
      const Eigen::Vector2d q = to_image * triangle_centroid(mesh, t);
      for (const Target& target : samples[n])
        if (std::hypot(q.x() - target.x, q.y() - target.y) < target.r)
          sigma[t] = target.cls == 1 ? 0.05 * sigma0 : 20 * sigma0;
    }
    const std::string number = std::to_string(n + 1);
    write_bytes_atomically(
        (dir / ("data" + number + ".mat")).string(),
        detail::mat_v5_bytes({mat("Inj", p.injection), mat("Mpat", p.measurement),
                              mat("Uel", model.measured(sigma))}));
    Eigen::MatrixXd truth = Eigen::MatrixXd::Zero(256, 256);
    const double w = 0.23 / 256;
    for (int i = 0; i < 256; ++i)
      for (int j = 0; j < 256; ++j)
        for (const Target& target : samples[n])
          if (std::hypot(-0.115 + (j + 0.5) * w - target.x, 0.115 - (i + 0.5) * w - target.y) <
              target.r)
            truth(i, j) = target.cls;
    detail::MatMatrix t = mat("truth", truth);
    t.uint8 = true;
    write_bytes_atomically((dir / ("true" + number + ".mat")).string(), detail::mat_v5_bytes({t}));
  }
}

}  // namespace eitbench::testing
