#include "gmsh_session.h"

#include <gmsh.h>
#include <omp.h>

#include <stdexcept>

namespace eitbench::detail {

std::mutex& gmsh_mutex() {
  static std::mutex m;
  return m;
}

GmshSession::GmshSession() : openmp_threads_(omp_get_max_threads()) {
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 0);
}

GmshSession::~GmshSession() {
  gmsh::finalize();
  omp_set_num_threads(openmp_threads_);
}

int distance_threshold(const std::vector<double>& curves, const std::vector<double>& points,
                       double size_min, double size_max, double dist_max) {
  namespace field = gmsh::model::mesh::field;
  const int distance = field::add("Distance");
  if (!curves.empty()) {
    field::setNumbers(distance, "CurvesList", curves);
    field::setNumber(distance, "NumPointsPerCurve", 200);
  }
  if (!points.empty()) field::setNumbers(distance, "PointsList", points);
  const int threshold = field::add("Threshold");
  field::setNumber(threshold, "InField", distance);
  field::setNumber(threshold, "SizeMin", size_min);
  field::setNumber(threshold, "SizeMax", size_max);
  field::setNumber(threshold, "DistMin", 0.0);
  field::setNumber(threshold, "DistMax", dist_max);
  return threshold;
}

void use_size_fields(const std::vector<double>& fields) {
  namespace field = gmsh::model::mesh::field;
  const int size = field::add("Min");
  field::setNumbers(size, "FieldsList", fields);
  field::setAsBackgroundMesh(size);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
  gmsh::option::setNumber("Mesh.Algorithm", 6);
  gmsh::option::setNumber("Mesh.Smoothing", 5);
}

SizeSet sizes_for(MeshDensity density) {
  switch (density) {
    case MeshDensity::coarse:
      return {0.4, 0.2, 0.085};
    case MeshDensity::medium:
      return {0.095, 0.05, 0.018};
    case MeshDensity::fine:
      return {0.036, 0.019, 0.0065};
  }
  throw std::logic_error("unknown mesh density");
}

}  // namespace eitbench::detail
