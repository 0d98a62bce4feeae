#pragma once
// The simulated tactile data set (docs/conventions.md): EdEIT-like circles on a fine mesh.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "eitbench/bench/data/dataset.h"
#include "eitbench/jacobian/disk_mesh.h"

namespace eitbench {

// What a simulated set may vary beyond the presets' touches, so that a model trained on it meets
// a real sensor (docs/real-presses.md#simulating-the-fitted-sensor): the touches' size and
// strength, and each sample's sensor drawn around the nominal one (domain randomisation). The
// defaults are the presets' own draws, and draw nothing more: the set is bit for bit the same.
struct SimulationVariation {
  // Each touch's radius (x R) and contrast c (sigma = sigma_0 (1 - c) inside), uniform in
  // [min, max]. Unset (max 0): the presets' 0.05-0.25 R, sigma uniform in [0.0001, 0.05] S/m.
  double radius_min = 0, radius_max = 0;
  double contrast_min = 0, contrast_max = 0;
  // Each sample's electrodes, each turned along the rim by U(-d, d) degrees (0: where the mesh
  // puts them): electrodes glued off their places. The disk only; d at most a quarter of the
  // narrowest gap between electrodes (2.8 degrees for 16 electrodes covering half the rim).
  double electrode_shift_deg = 0;
  // Each sample's contact impedances, each electrode's x exp(U(-s, s)) (0: the nominal ones).
  double impedance_spread = 0;
  // Each sample's channel gains, each 1 + N(0, g) (0: exact).
  double gain_error = 0;
  // Each sample's change with white noise at an SNR uniform in [min, max] dB (max 0: none).
  double snr_min_db = 0, snr_max_db = 0;
  // A real sensor's measured channel gains (one a channel of the protocol; NaN: none) and noise
  // (each value's RMS over the reference frame's RMS), as calibrate --noise measures them on its
  // unlabelled frames (docs/real-presses.md): every sample's change times the gains, plus that
  // noise, after the draws above. Empty and 0: off.
  Eigen::VectorXd sensor_gains;
  double sensor_noise = 0;

  bool touches_set() const { return radius_max > 0; }
  bool like_sensor() const { return sensor_gains.size() > 0 || sensor_noise > 0; }
  bool randomised() const {
    return electrode_shift_deg > 0 || impedance_spread > 0 || gain_error > 0 || snr_max_db > 0 ||
           like_sensor();
  }
  // InputError naming the flag (--touch-radius, --touch-contrast, --randomise-...) of a bad value
  // (the electrode shift's bound, which depends on the mesh, is checked where it is simulated).
  void validate() const;
};
// "touches 0.2-0.35 R, contrast 0-0.3; randomised: electrodes +-2 deg, impedances x e^U(-0.5,
// 0.5), gains 2 %, SNR 25-50 dB"; "" for the defaults.
std::string describe(const SimulationVariation& v);
// A set's simulation_mesh: the mesh's description, then the variation's when there is one (what a
// resumed run compares).
std::string with_variation(const std::string& mesh, const SimulationVariation& v);

struct SimulationOptions {
  std::string preset = "quick";  // quick | standard | paper (sample counts)
  std::uint64_t seed = 1;
  int threads = 0;  // 0: all cores
  int electrodes = 16;
  MeshDensity density = MeshDensity::fine;  // finer than the reconstruction mesh (medium)
  double background = 0.05;
  double contact_impedance = 0.01;
  double current = 1.0;
  double electrode_coverage = 0.5;
  int image_size = 64;
  // A sensor of another shape (docs/sensors.md): its mesh, with electrode_k groups, and where it
  // came from (a file name, for the set's description). Null: the disk of `electrodes`. The frames
  // are then made on the mesh refined once (refine_mesh), touches drawn inside it, the labels on
  // the grid covering it, and the set stores the mesh and its symmetry group.
  std::shared_ptr<const Mesh> sensor_mesh;
  std::string sensor_source;
  // The measurement protocol the frames are read on (docs/protocols.md), with its magnitude flag.
  // Null: the adjacent protocol, rotating order. Its electrodes must be the sensor's.
  std::shared_ptr<const MeasurementProtocol> protocol;
  SimulationVariation variation;  // the touches' sizes, domain randomisation
  // This process's part of the set (docs/scaling.md): shard `shard_index` of `shard_count`, the
  // whole set's rows n K / N .. n (K + 1) / N - 1. Each sample draws from its own stream, seeded by
  // its index in the whole set, so the shards joined in order are the whole set bit for bit.
  int shard_index = 0, shard_count = 1;
};

// Samples with 1, 2, 3 and 4 circles for a preset: paper 7,035 / 7,298 / 7,500 / 7,500; standard
// and quick the same proportions scaled to about 5,500 and 2,000 training samples. Train: all 1-3
// circle samples; validation and test: 2/3 and 1/3 of the 4-circle ones.
struct PresetCounts {
  int circles[4];
  int validation;  // of the 4-circle samples; the rest are test
};
PresetCounts preset_counts(const std::string& preset);  // throws InputError naming --preset

// Shard K of N's rows [first, last) of a set of n samples (SimulationOptions' shard); throws
// InputError naming --shard unless 0 <= K < N.
std::pair<int, int> shard_rows(const SimulationOptions& options, int n);

// Called now and then with (samples done, total).
using ProgressFn = std::function<void(int, int)>;

// Deterministic for a seed, whatever the thread count: sample i draws from its own generator.
Dataset simulate_dataset(const SimulationOptions& options, const ProgressFn& progress = {});

}  // namespace eitbench
