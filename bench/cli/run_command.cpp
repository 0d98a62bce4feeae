// eitbench run: the main job. For now it exercises the foundation end to end (meshes, forward
// model, Jacobian) and prints what it measured; the benchmark issue turns it into the full run.
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>

#include "commands.h"
#include "eitbench/bench/figures.h"
#include "eitbench/bench/io.h"
#include "eitbench/bench/timing.h"
#include "eitbench/bench/version.h"
#include "eitbench/jacobian.h"

namespace eitbench::cli {
namespace {

// Median wall time of `repeats` calls, in milliseconds.
template <typename F>
double median_ms(int repeats, F&& f) {
  return percentile(time_calls_ms(repeats, std::forward<F>(f)), 0.5);
}

}  // namespace

std::function<void()> add_run_command(CLI::App& app) {
  struct Args {
    std::string preset = "quick", out;
    int electrodes = 16;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "run", "The main job: build the sensor model end to end and report what it measured");
  cmd->add_option("--preset", args->preset, "quick | standard | paper")
      ->capture_default_str()
      ->check(CLI::IsMember({"quick", "standard", "paper"}));
  cmd->add_option("--electrodes", args->electrodes, "electrodes L")
      ->capture_default_str()
      ->check(CLI::Range(4, 256));
  cmd->add_option("--out", args->out, "folder for the outputs (default out/<preset>)");
  return [args] {
    namespace fs = std::filesystem;
    const std::string out = args->out.empty() ? "out/" + args->preset : args->out;
    fs::create_directories(out);
    const int L = args->electrodes;
    // Reconstruction mesh and a finer simulation mesh: data never come from the mesh that inverts
    // them. The presets differ in data-set size (issue 7), not in meshes.
    const MeshDensity recon_density = MeshDensity::medium;
    const MeshDensity sim_density = MeshDensity::fine;
    fmt::print("{} run --preset {}: L = {} electrodes, output in {}/\n", program_version(),
               args->preset, L, out);

    fmt::print("[1/5] meshes with exact D_{} symmetry\n", L);
    Mesh recon, sim;
    const double recon_ms = median_ms(1, [&] { recon = generate_disk_mesh({L, recon_density}); });
    const double sim_ms = median_ms(1, [&] { sim = generate_disk_mesh({L, sim_density}); });
    for (const auto& [name, mesh, ms] : {std::tuple{to_string(recon_density), &recon, recon_ms},
                                         std::tuple{to_string(sim_density), &sim, sim_ms}}) {
      const MeshQuality q = measure_quality(*mesh);
      fmt::print("      {:<7} {:>6} nodes {:>6} triangles, smallest angle {:5.2f} deg, {:.1f} ms\n",
                 name, q.nodes, q.triangles, q.min_angle_deg, ms);
    }
    write_text_atomically(out + "/mesh.msh",
                          [&](std::ostream& s) { write_msh(s, recon, MshVersion::v41); });
    draw_mesh_png(recon, out + "/mesh.png");

    fmt::print("[2/5] forward model: homogeneous disk, sigma = 1 S/m, I = 1 A, z_c = 0.01\n");
    const ForwardModel recon_model(recon), sim_model(sim);
    const Eigen::VectorXd one = Eigen::VectorXd::Ones(recon.num_triangles());
    ForwardSolution solution;
    const double forward_ms = median_ms(20, [&] { solution = recon_model.solve(one); });
    const Eigen::VectorXd v0 = recon_model.frame(solution);
    const Eigen::MatrixXd currents = recon_model.electrode_currents(solution);
    fmt::print(
        "      {} values, |v| max {:.5f} V; reciprocity error {:.1e}; current balance {:.1e}; "
        "{:.2f} ms for all {} drives\n",
        v0.size(), v0.cwiseAbs().maxCoeff(),
        recon_model.protocol().reciprocity_error(v0, MeasurementOrder::rotating),
        currents.colwise().sum().cwiseAbs().maxCoeff(), forward_ms, L);

    fmt::print("[3/5] a two-finger touch, simulated on the {} mesh\n", to_string(sim_density));
    const std::vector<Circle> touch{{0.45, 0.10, 0.2, 0.02}, {-0.30, -0.35, 0.15, 0.03}};
    const double background = 0.05;
    const Eigen::VectorXd sigma = conductivity_from_circles(sim, touch, background);
    const Eigen::VectorXd ref =
        sim_model.frame(Eigen::VectorXd::Constant(sim.num_triangles(), background));
    const Eigen::VectorXd touched = sim_model.frame(sigma);
    const Eigen::VectorXd dv = touched - ref;
    write_frames_csv(out + "/frame.csv", touched.transpose());
    fmt::print("      |dv| / |v| = {:.2f} %, largest change {:.3g} V at measurement {}\n",
               100 * dv.norm() / ref.norm(), dv.cwiseAbs().maxCoeff(), [&] {
                 Eigen::Index i;
                 dv.cwiseAbs().maxCoeff(&i);
                 return i;
               }());

    fmt::print("[4/5] Jacobian by the adjoint method on the {} mesh\n", to_string(recon_density));
    Eigen::MatrixXd J;
    const double jac_ms = median_ms(20, [&] { J = recon_model.jacobian(one); });
    const PixelGrid grid(64, 1.0);
    Eigen::SparseMatrix<double, Eigen::RowMajor> P;
    const double map_ms = median_ms(1, [&] { P = pixel_to_element(recon, grid); });
    Eigen::MatrixXd Jp;
    const double pix_ms = median_ms(5, [&] { Jp = J * P; });
    fmt::print(
        "      elements: {} x {} in {:.2f} ms (forward included); pixels: {} x {} ({} in the "
        "disk), map {:.1f} ms once, product {:.2f} ms\n",
        J.rows(), J.cols(), jac_ms, Jp.rows(), Jp.cols(), grid.num_inside(), map_ms, pix_ms);
    Hdf5Matrix content;
    content.name = "jacobian";
    content.matrix = &J;
    content.text_attributes = {
        {"basis", "elements"}, {"order", "rotating"}, {"program", program_version()}};
    content.number_attributes = {{"electrodes", double(L)},
                                 {"triangles", double(recon.num_triangles())}};
    write_hdf5_matrix(out + "/jacobian.h5", content);

    fmt::print("[5/5] linearisation check: J * dsigma against the simulated change\n");
    const Eigen::VectorXd sigma_recon = conductivity_from_circles(recon, touch, background);
    const Eigen::VectorXd base = Eigen::VectorXd::Constant(recon.num_triangles(), background);
    const Eigen::VectorXd linear = recon_model.jacobian(base) * (sigma_recon - base);
    const double cc = [&] {
      const Eigen::ArrayXd a = linear.array() - linear.mean(), b = dv.array() - dv.mean();
      return (a * b).sum() / std::sqrt((a * a).sum() * (b * b).sum());
    }();
    fmt::print(
        "      correlation {:.4f}, relative difference {:.3f} (a linear model of a large change on "
        "another mesh)\n",
        cc, (linear - dv).norm() / dv.norm());
    fmt::print("done: wrote mesh.msh, mesh.png, frame.csv, jacobian.h5 in {}/\n", out);
  };
}

}  // namespace eitbench::cli
