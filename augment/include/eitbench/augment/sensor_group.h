#pragma once
// The symmetry group of a sensor, found from its mesh: the isometries of the plane that map the
// domain's boundary and the electrode set onto themselves (docs/sensors.md).
//
// Every such isometry permutes the electrodes; because electrodes are numbered along the boundary,
// the permutation is a rotation or a reflection of the cycle 0 .. L-1, that is, an element of D_L
// acting on electrode indices. Its action on frames is therefore FrameSymmetry's for that
// GroupElement, whatever the sensor's shape; only its action on points (touches, images) is the
// sensor's own, which SensorSymmetry carries.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "eitbench/augment/symmetry.h"
#include "eitbench/jacobian/mesh.h"
#include "eitbench/jacobian/pixel_grid.h"

namespace eitbench {

// x -> centre + linear (x - centre): a rotation (det +1) or a reflection (det -1) about `centre`.
struct Isometry {
  Eigen::Matrix2d linear = Eigen::Matrix2d::Identity();
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();

  Eigen::Vector2d operator()(const Eigen::Vector2d& x) const {
    return centre + linear * (x - centre);
  }
  bool is_reflection() const { return linear(0, 0) * linear(1, 1) < linear(0, 1) * linear(1, 0); }
  Isometry inverse() const { return {linear.transpose(), centre}; }
  // "rotation by 90 deg" or "mirror, axis at 22.5 deg" (angles counter-clockwise from +x).
  std::string describe() const;
};

struct SensorSymmetry {
  GroupElement element;         // its action on frames, as FrameSymmetry applies it
  Isometry map;                 // its action on the plane: a touch at x moves to map(x)
  std::vector<int> electrodes;  // electrode e lands on electrode electrodes[e]
};

struct SymmetrySearchOptions {
  // Points match when they are this close, as a fraction of the median boundary segment: loose
  // enough for an unsymmetric mesh of a symmetric shape (its boundary nodes lie off each other's
  // chords by a sagitta, h^2 / 8 rho), tight against any real asymmetry of the layout. (0, 1].
  double relative_tolerance = 0.25;

  void validate() const;  // InputError("SymmetrySearchOptions", field)
};

struct SensorGroup {
  int electrodes = 0;
  double tolerance = 0;                  // in the mesh's length unit
  Eigen::Vector2d centre;                // the domain's centroid, which every isometry fixes
  std::vector<SensorSymmetry> elements;  // identity first, then rotations by angle, then mirrors

  int order() const { return static_cast<int>(elements.size()); }
  bool has_reflections() const;
  // "D4" (8 elements: 4 rotations and 4 mirrors), "C2", "D1" (one mirror), "trivial".
  std::string name() const;
  // The smallest rotation and, when there is one, the first mirror: together they make the group.
  std::vector<SensorSymmetry> generators() const;
  // The element acting on frames as g does; nullptr when the sensor lacks it.
  const SensorSymmetry* find(const GroupElement& g) const;
  std::vector<GroupElement> frame_elements() const;
};

// A sensor of any shape as augmentation sees it: the group found from its mesh, whose isometries
// move touches and labels, and the pixel grid covering it (PixelGrid::covering).
struct ShapedSensor {
  SensorGroup group;
  PixelGrid grid;
};

// Throws InputError(source, ...) for a mesh with point electrodes all at one place, or for bad
// options. Deterministic; O(candidates x boundary nodes^2) with at most 2L candidates surviving
// the electrode test.
SensorGroup find_sensor_group(const Mesh& mesh, const SymmetrySearchOptions& options = {},
                              const std::string& source = "mesh");

// The group and the covering grid of `mesh`, images image_size pixels a side.
ShapedSensor shaped_sensor(const Mesh& mesh, int image_size,
                           const SymmetrySearchOptions& options = {},
                           const std::string& source = "mesh");

// Refuses (InputError naming `source` and the electrode that breaks it) any element of `elements`
// the sensor does not have, e.g. "rot:1 is not a symmetry of this sensor: turned so that electrode
// 0 lands on electrode 15, electrode 3 lands 0.31 from electrode 2".
void require_sensor_symmetries(const std::vector<GroupElement>& elements, const Mesh& mesh,
                               const SensorGroup& group, const std::string& source);

}  // namespace eitbench
