#pragma once
// A data set of frames and touch labels, simulated or imported: its schema. The HDF5 file that
// holds it is dataset_file.h's.
//
// File layout (HDF5, readable by h5py and MATLAB's h5read; N samples, L electrodes, n x n image):
//   /differences   N x I         float64  difference voltages v(sigma) - v(sigma_0): the protocol's
//                                         I inputs (the adjacent protocol's reduced 104)
//   /frames        N x C         float64  absolute frames, the protocol's C channels in order
//                                         (the adjacent protocol's 208 in rotating order)
//   /reference     C             float64  the reference (empty sensor) frame
//   /protocol_channels C x 4     int32    drive+, drive-, meas+, meas- per channel (0-based);
//                                         absent in files before protocols: the adjacent one
//   /split         N             int32    0 train, 1 validation, 2 test
//   /labels        N x n x n     float32  touch intensity (sigma_0 - sigma) / sigma_0 per pixel
//   /circles       N x 4 x 4     float64  x, y, r, sigma of up to 4 circles, NaN-padded
//   /circle_count  N             int32
//   /touches       N x 4 x 3     float64  a press set's known touches: x, y and size (the probe's
//                                         radius or the press depth, NaN if unknown), NaN-padded
//   /touch_count   N             int32
//   /references    N x C         float64  a press set's reference recorded before each frame
//                                         (import --paired-reference): repeated frames of the
//                                         untouched sensor, on which calibrate --noise measures
//                                         its noise and drift
//   /sensor_mesh   bytes         uint8    a sensor of another shape: its mesh as Gmsh 4.1 text
//                                         (absent for the disk, which the attributes describe)
// Labels and circles are absent from imported measurements; touches only in press sets (import
// --touches), with the attribute touch_size (radius, depth or empty). Attributes on the root group:
// electrodes, radius, background_conductivity, contact_impedance, current, electrode_coverage,
// image_size, seed, preset, simulation_mesh, simulation_triangles, protocol (its name),
// magnitude (1 when the frames are |v|), frame_order, difference_layout, program, augmentation,
// format_version, and with a sensor mesh sensor_group (the symmetry group found from it, for the
// reader's information). A shard (simulate --shard K/N) also has shard_index, shard_count,
// shard_first and shard_total: its rows are the whole set's shard_first onwards.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "eitbench/jacobian/geometry.h"
#include "eitbench/jacobian/measurement_protocol.h"
#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench {

enum class Split : int { train = 0, validation = 1, test = 2 };
std::string to_string(Split split);

// A pressed touch's truth in a press set (measured frames with known touches, docs/data.md): its
// centre in the mesh's unit and its size, the probe's radius or the press's depth as
// Dataset::touch_size says, NaN where not known.
struct PressTouch {
  double x = 0, y = 0, size = NAN;
};

// Which part of a set a file holds: the whole set, or shard `index` of `count`, whose rows are the
// whole set's rows first .. first + size - 1 of `total` (docs/scaling.md). Commands that use a set
// refuse a shard; `eitbench merge` joins them.
struct Shard {
  int index = 0, count = 1;
  long long first = 0, total = 0;
  bool whole() const { return count == 1; }
};

struct Dataset {
  // Sensor and protocol.
  int electrodes = 16;
  double radius = 1.0;
  double background = 0.05;  // sigma_0 (S/m)
  double contact_impedance = 0.01;
  double current = 1.0;
  double electrode_coverage = 0.5;
  int image_size = 64;
  // Provenance.
  std::uint64_t seed = 0;
  std::string preset;           // quick | standard | paper | imported
  std::string simulation_mesh;  // how the frames were made, or where they came from
  int simulation_triangles = 0;
  std::string program;
  std::string augmentation = "none";  // the group the set was expanded by, if any
  // A sensor of another shape (docs/sensors.md): its mesh as Gmsh 4.1 text, on which the run
  // reconstructs and whose grid the labels are on; empty for the disk of `radius`.
  std::string sensor_mesh;
  std::string sensor_group;  // its symmetry group's name ("D4"), as found when it was simulated
  // The measurement protocol (docs/protocols.md): its name and channels (empty: the adjacent
  // protocol in rotating order), and whether frames are magnitudes |v|.
  std::string protocol = "adjacent";
  std::vector<Channel> protocol_channels;
  bool magnitude = false;

  Eigen::VectorXd reference;                 // C, the protocol's channels
  SampleMatrix frames;                       // N x C
  SampleMatrix differences;                  // N x I, the protocol's inputs
  SampleMatrix labels;                       // N x n^2, or N x 0
  std::vector<std::vector<Circle>> circles;  // N lists, or empty
  // A press set's known touches: N lists of at most 4, or empty; and what their size holds:
  // "radius", "depth", or "" (none known).
  std::vector<std::vector<PressTouch>> touches;
  std::string touch_size;
  // Each frame's own reference (import --paired-reference): N x C, or 0 rows.
  SampleMatrix references;
  std::vector<Split> split;  // N
  Shard shard;

  int size() const { return static_cast<int>(differences.rows()); }
  bool has_labels() const { return labels.cols() > 0; }
  std::vector<int> indices(Split which) const;
};

// The set's protocol (checked: InputError("protocol") when its channels do not fit).
MeasurementProtocol measurement_protocol(const Dataset& data);
// Records `protocol` in the set (its name, channels and magnitude flag).
void set_protocol(Dataset& data, const MeasurementProtocol& protocol);

}  // namespace eitbench
