// eitbench mesh: generate (or read) a mesh, report its quality, write it as Gmsh and as a picture.
#include <fmt/core.h>

#include <fstream>
#include <memory>

#include "commands.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/report/figures.h"
#include "options.h"

namespace eitbench::cli {

std::function<void()> add_mesh_command(CLI::App& app) {
  struct Args {
    MeshSource mesh;
    std::string out, png, format = "4.1", cache;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "mesh", "Generate a D_L-symmetric disk mesh (or read one); report and write it");
  add_mesh_options(*cmd, args->mesh);
  cmd->add_option("--out", args->out, "write the mesh as Gmsh ASCII (.msh)");
  cmd->add_option("--msh-version", args->format, "Gmsh format of --out: 2.2 | 4.1")
      ->capture_default_str()
      ->check(CLI::IsMember({"2.2", "4.1"}));
  cmd->add_option("--png", args->png, "draw the mesh with its electrodes to a PNG");
  cmd->add_option("--cache", args->cache,
                  "also write the generated mesh into this folder under its options' name, "
                  "where a build without Gmsh reads it (EITBENCH_MESH_DIR)");
  return [args] {
    const Mesh mesh = load_mesh(args->mesh);
    const MeshQuality q = measure_quality(mesh);
    const auto areas = triangle_areas(mesh);
    fmt::print("mesh: {} nodes, {} triangles, {} electrodes, {} boundary segments\n", q.nodes,
               q.triangles, mesh.num_electrodes(), q.boundary_segments);
    fmt::print(
        "angles: smallest {:.2f} deg, largest {:.2f} deg; areas {:.3g} .. {:.3g} (total {:.6f})\n",
        q.min_angle_deg, q.max_angle_deg, q.min_area, q.max_area, areas.sum());
    if (mesh.reoriented > 0)
      fmt::print(
          "orientation: {} of {} triangles were clockwise in {} and were turned "
          "counter-clockwise (the same geometry)\n",
          mesh.reoriented, q.triangles, args->mesh.file);
    if (!args->out.empty()) {
      write_text_atomically(args->out, [&](std::ostream& out) {
        write_msh(out, mesh, args->format == "2.2" ? MshVersion::v22 : MshVersion::v41);
      });
      fmt::print("wrote {}\n", args->out);
    }
    if (!args->cache.empty()) {
      if (!args->mesh.file.empty())
        throw InputError("--cache", "", "keeps generated meshes only, not --mesh files");
      const std::string path = args->cache + "/" + disk_mesh_file_name(args->mesh.disk);
      write_text_atomically(path,
                            [&](std::ostream& out) { write_msh(out, mesh, MshVersion::v41); });
      fmt::print("wrote {}\n", path);
    }
    if (!args->png.empty()) {
      draw_mesh_png(mesh, args->png);
      fmt::print("wrote {}\n", args->png);
    }
  };
}

}  // namespace eitbench::cli
