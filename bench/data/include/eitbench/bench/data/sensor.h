#pragma once
// The sensor a data set was made on, as the commands that use it need it: the disk (generated from
// the set's attributes) or a sensor of another shape whose mesh the set stores (docs/sensors.md).
#include <memory>
#include <string>
#include <vector>

#include "eitbench/augment/sensor_group.h"
#include "eitbench/bench/data/dataset.h"
#include "eitbench/jacobian/disk_mesh.h"
#include "eitbench/jacobian/mesh.h"
#include "eitbench/jacobian/pixel_grid.h"

namespace eitbench {

// True when the set stores a mesh of its own (a sensor of another shape).
inline bool has_sensor_mesh(const Dataset& data) {
  return !data.sensor_mesh.empty();
}

// The stored mesh, parsed (the reader has checked it); InputError when the set has none.
Mesh stored_sensor_mesh(const Dataset& data);

// The mesh to reconstruct on: the disk of the set's attributes at `density`, or the stored mesh as
// it is (a user's mesh is the sensor; it has no density to choose).
Mesh reconstruction_mesh(const Dataset& data, MeshDensity density);

// The label images' grid: the disk's [-R, R]^2, or the grid covering the stored mesh.
PixelGrid image_grid(const Dataset& data);

// The grid's mask as the learned decoder takes it (NetworkOptions::mask): empty for the disk.
std::vector<bool> sensor_mask(const Dataset& data);

// The stored sensor's group and grid, for augmentation; null for the disk.
std::shared_ptr<const ShapedSensor> shaped_sensor_of(const Dataset& data);

// A mesh as Gmsh 4.1 text, as Dataset::sensor_mesh holds it.
std::string mesh_text(const Mesh& mesh);

// Each triangle split in four at its edges' midpoints, each electrode segment in two: the same
// domain and electrodes, twice as fine. The simulation's mesh for a sensor given as a mesh, so
// that its frames are not made on the very mesh they are reconstructed on.
Mesh refine_mesh(const Mesh& mesh);

}  // namespace eitbench
