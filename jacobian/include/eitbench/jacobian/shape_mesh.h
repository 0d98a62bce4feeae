#pragma once
// Sensors of other shapes: a rectangle (a square) with electrodes along its sides, an ellipse, or a
// disk with electrodes anywhere on its rim, meshed by Gmsh (docs/sensors.md). Unlike the disk's
// generator, the mesh is not built symmetric: the symmetry group is found from the geometry, within
// a tolerance (augment/sensor_group.h).
#include <string>
#include <vector>

#include "eitbench/jacobian/disk_mesh.h"
#include "eitbench/jacobian/mesh.h"

namespace eitbench {

enum class SensorShape { disk, rectangle, ellipse };

// disk | rectangle | ellipse; InputError("SensorShape", "name") otherwise.
SensorShape parse_shape(const std::string& name);
std::string to_string(SensorShape shape);

struct ShapeMeshOptions {
  SensorShape shape = SensorShape::rectangle;
  int electrodes = 16;  // L, 4 <= L <= 256
  // The rectangle's sides, or the ellipse's axes (2a x 2b), centred at the origin; a disk's
  // diameter (both equal). Positive and finite, their ratio at most 20.
  double width = 2.0, height = 2.0;
  // The fraction of the perimeter under electrodes, strictly between 0 and 1; each is coverage/L.
  double electrode_coverage = 0.5;
  // Electrode centres as fractions of the perimeter (arc length), counter-clockwise from the
  // boundary point on the +x axis, increasing in [0, 1), electrodes not overlapping. Empty: evenly
  // spaced at (e + 1/2) / L, which puts a rectangle's corners in gaps (16 electrodes on a square:
  // 4 a side, the group D4). A disk with them empty is generate_disk_mesh's (electrode e at
  // e / L, exactly D_L-symmetric).
  std::vector<double> electrode_positions;
  MeshDensity density = MeshDensity::medium;
  double size_factor = 1.0;  // as DiskMeshOptions::size_factor, in [0.1, 10]

  // Throws InputError("ShapeMeshOptions", field) for a value out of range.
  void validate() const;
};

// Validates, then meshes. Electrode e is one boundary stretch of length coverage * perimeter / L
// centred at its position; the mesh is finer towards electrode edges as the disk's is, at sizes
// scaled by sqrt(width * height) / 2. Deterministic. A build without Gmsh throws InputError,
// except for the symmetric disk (generate_disk_mesh's files).
Mesh generate_shape_mesh(const ShapeMeshOptions& options);

// The point at fraction s of the perimeter (counter-clockwise from the +x axis) of the options'
// shape: where generate_shape_mesh puts electrode edges.
struct PerimeterPoint {
  double x, y;
};
PerimeterPoint perimeter_point(const ShapeMeshOptions& options, double s);

}  // namespace eitbench
