#pragma once
// A 2-D triangle mesh with boundary electrodes: the geometry every other module works on.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace eitbench {

using Points = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;  // one node a row
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;  // counter-clockwise

// An electrode is either a set of boundary segments (the complete electrode model integrates over
// them) or a single node (a point electrode, whose contact impedance is then lumped at that node).
struct Electrode {
  std::vector<std::array<int, 2>> segments;
  int point_node = -1;

  bool is_point() const { return segments.empty(); }
  double length(const Points& nodes) const;
};

struct Mesh {
  Points nodes;
  Triangles triangles;
  std::vector<Electrode> electrodes;  // electrode e at index e, counter-clockwise
  // Triangles a reader found clockwise and turned (EIDORS's meshes mix both orientations): what
  // `eitbench mesh --mesh FILE` reports. The geometry is the same either way.
  int reoriented = 0;

  int num_nodes() const { return static_cast<int>(nodes.rows()); }
  int num_triangles() const { return static_cast<int>(triangles.rows()); }
  int num_electrodes() const { return static_cast<int>(electrodes.size()); }
};

struct MeshQuality {
  int nodes = 0;
  int triangles = 0;
  int boundary_segments = 0;
  double min_angle_deg = 0;
  double max_angle_deg = 0;
  double min_area = 0;
  double max_area = 0;
};

Eigen::VectorXd triangle_areas(const Mesh& mesh);
// The edges that belong to one triangle only, each as (smaller node, larger node), in that order.
std::vector<std::array<int, 2>> boundary_edges(
    const Mesh& mesh);  // signed: positive when counter-clockwise
Eigen::Vector2d triangle_centroid(const Mesh& mesh, int t);
MeshQuality measure_quality(const Mesh& mesh);

// Checks what the solver relies on and throws InputError(source, field, ...) otherwise: indices in
// range, every triangle counter-clockwise with positive area, no two triangles overlapping (an
// edge crossed twice in the same direction: a folded mesh), every electrode non-empty and on the
// boundary, no two electrodes sharing a node, one connected piece. `source` names the file.
void validate_mesh(const Mesh& mesh, const std::string& source);

// Turns every clockwise triangle counter-clockwise (counted in mesh.reoriented: a surface meshed
// with its normal along -z, or EIDORS's mixed orientation), and drops nodes that no triangle uses,
// renumbering electrodes to match. A triangle that was clockwise because the mesh folds over
// itself then overlaps its neighbour, which validate_mesh refuses.
void normalize_mesh(Mesh& mesh);

}  // namespace eitbench
