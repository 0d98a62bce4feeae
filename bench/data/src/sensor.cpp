#include "eitbench/bench/data/sensor.h"

#include <map>
#include <sstream>
#include <utility>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/msh_io.h"

namespace eitbench {

Mesh stored_sensor_mesh(const Dataset& data) {
  if (!has_sensor_mesh(data))
    throw InputError("data set", "sensor_mesh", "the set is on the disk; it stores no mesh");
  std::istringstream in(data.sensor_mesh);
  return read_msh(in, "the data set's sensor_mesh");
}

Mesh reconstruction_mesh(const Dataset& data, MeshDensity density) {
  if (has_sensor_mesh(data)) return stored_sensor_mesh(data);
  DiskMeshOptions disk;
  disk.electrodes = data.electrodes;
  disk.density = density;
  disk.radius = data.radius;
  disk.electrode_coverage = data.electrode_coverage;
  return generate_disk_mesh(disk);
}

PixelGrid image_grid(const Dataset& data) {
  if (has_sensor_mesh(data)) return PixelGrid::covering(stored_sensor_mesh(data), data.image_size);
  return PixelGrid(data.image_size, data.radius);
}

std::vector<bool> sensor_mask(const Dataset& data) {
  std::vector<bool> mask;
  if (!has_sensor_mesh(data)) return mask;
  const PixelGrid grid = image_grid(data);
  for (Eigen::Index p = 0; p < grid.mask().size(); ++p) mask.push_back(grid.mask()[p]);
  return mask;
}

std::shared_ptr<const ShapedSensor> shaped_sensor_of(const Dataset& data) {
  if (!has_sensor_mesh(data)) return nullptr;
  return std::make_shared<const ShapedSensor>(
      shaped_sensor(stored_sensor_mesh(data), data.image_size, {}, "the data set's sensor_mesh"));
}

std::string mesh_text(const Mesh& mesh) {
  std::ostringstream out;
  write_msh(out, mesh, MshVersion::v41);
  return out.str();
}

Mesh refine_mesh(const Mesh& mesh) {
  Mesh out;
  std::map<std::pair<int, int>, int> midpoint;
  std::vector<Eigen::Vector2d> nodes;
  for (int k = 0; k < mesh.num_nodes(); ++k) nodes.push_back(mesh.nodes.row(k));
  auto middle = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    const auto [it, added] = midpoint.try_emplace({key.first, key.second}, 0);
    if (added) {
      it->second = static_cast<int>(nodes.size());
      nodes.push_back(0.5 * (nodes[a] + nodes[b]));
    }
    return it->second;
  };
  std::vector<std::array<int, 3>> triangles;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const int a = mesh.triangles(t, 0), b = mesh.triangles(t, 1), c = mesh.triangles(t, 2);
    const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
    triangles.insert(triangles.end(), {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}});
  }
  for (const Electrode& e : mesh.electrodes) {
    Electrode split;
    split.point_node = e.point_node;
    for (const auto& [a, b] : e.segments) {
      const int m = middle(a, b);
      split.segments.push_back({a, m});
      split.segments.push_back({m, b});
    }
    out.electrodes.push_back(split);
  }
  out.nodes.resize(static_cast<Eigen::Index>(nodes.size()), 2);
  for (std::size_t k = 0; k < nodes.size(); ++k)
    out.nodes.row(static_cast<Eigen::Index>(k)) = nodes[k];
  out.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) out.triangles(static_cast<Eigen::Index>(t), k) = triangles[t][k];
  return out;
}

}  // namespace eitbench
