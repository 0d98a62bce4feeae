// eitbench simulate: the simulated tactile data set (docs/conventions.md) as an HDF5 file.
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>

#include "commands.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/dataset_shards.h"
#include "eitbench/bench/data/simulate.h"
#include "eitbench/bench/support/progress.h"
#include "eitbench/bench/support/timing.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/msh_io.h"
#include "options.h"
#include "world.h"

namespace eitbench::cli {
namespace {

// Simulates the set, or the options' shard of it, into `out`; `summary`: the closing line even
// when quiet.
void simulate_to(const SimulationOptions& o, const std::string& mesh_label, const std::string& out,
                 bool quiet, bool summary = true) {
  const auto counts = preset_counts(o.preset);
  int total = 0;
  for (int c : counts.circles) total += c;
  if (!quiet)
    fmt::print(
        "simulating {} samples ({} / {} / {} / {} with 1 / 2 / 3 / 4 circles), seed {}, {} "
        "protocol ({} channels{}), {} mesh\n",
        total, counts.circles[0], counts.circles[1], counts.circles[2], counts.circles[3], o.seed,
        o.protocol->name(), o.protocol->size(), o.protocol->magnitude() ? ", magnitudes" : "",
        mesh_label);
  const auto [first, last] = shard_rows(o, total);
  const int rows = last - first;
  if (o.shard_count > 1 && !quiet)
    fmt::print("shard {} of {}: {} of those samples\n", o.shard_index, o.shard_count, rows);
  Progress progress("simulate", std::max(rows, 1), quiet);
  const auto t0 = std::chrono::steady_clock::now();
  const Dataset data = simulate_dataset(o, [&](int done, int) { progress.update(done); });
  const double seconds = seconds_since(t0);
  if (!data.sensor_mesh.empty() && !quiet)
    fmt::print("sensor {}: symmetry group {}\n", o.sensor_source, data.sensor_group);
  write_dataset(out, data);
  if (summary)
    fmt::print(
        "wrote {}: {} samples (train {}, validation {}, test {}) in {:.1f} s, {:.0f} samples/s\n",
        out, data.size(), data.indices(Split::train).size(), data.indices(Split::validation).size(),
        data.indices(Split::test).size(), seconds, data.size() / seconds);
}

// Under mpirun (docs/scaling.md): rank K of N simulates shard K into OUT's shard file, then rank 0
// joins the shards into OUT and removes them. Every rank reaches the collective whatever happened
// to it, so one rank's failure ends every rank, its own with its message; the shard files that
// were finished stay.
void simulate_by_rank(SimulationOptions o, const std::string& mesh_label, const std::string& out,
                      bool quiet, World w) {
  o.shard_index = w.rank, o.shard_count = w.size;
  std::vector<std::string> files;
  for (int k = 0; k < w.size; ++k) files.push_back(shard_file_name(out, k, w.size));
  on_every_rank([&] { simulate_to(o, mesh_label, files[w.rank], quiet || w.rank != 0, false); },
                files[w.rank] + " is kept");
  if (w.rank != 0) return;
  const ShardMerge merged = merge_dataset_shards(files, out);
  for (const std::string& f : files) std::filesystem::remove(f);
  fmt::print("wrote {}: {} samples, simulated as {} shards by {} MPI ranks\n", out, merged.samples,
             merged.shards, w.size);
}

}  // namespace

std::function<void()> add_simulate_command(CLI::App& app) {
  struct Args {
    SimulationOptions options;
    std::string density = "fine", mesh, out;
    bool quiet = false;
    ProtocolChoice protocol;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "simulate", "Simulate the EdEIT-like tactile data set (circles on a fine mesh) to HDF5");
  cmd->add_option("--preset", args->options.preset,
                  "quick (~2,000 training samples) | standard (~5,500) | paper (21,833)")
      ->capture_default_str()
      ->check(CLI::IsMember({"quick", "standard", "paper", "tiny"}));
  cmd->add_option("--seed", args->options.seed, "random seed: the same seed gives the same file")
      ->capture_default_str();
  cmd->add_option("--threads", args->options.threads,
                  "worker threads (0: all cores); the output does not depend on it")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--electrodes", args->options.electrodes, "electrodes L")
      ->capture_default_str()
      ->check(CLI::Range(4, 256));
  cmd->add_option("--density", args->density,
                  "simulation mesh: coarse | medium | fine (reconstructions use medium)")
      ->capture_default_str()
      ->check(CLI::IsMember({"coarse", "medium", "fine"}));
  cmd->add_option("--mesh", args->mesh,
                  "a sensor of any shape: Gmsh mesh with electrode_0.. groups (eitbench mesh "
                  "--shape makes one); frames on it refined once, touches inside it, its symmetry "
                  "group and the mesh recorded in the set")
      ->excludes("--electrodes")
      ->excludes("--density");
  cmd->add_option("--background", args->options.background, "background conductivity sigma_0 (S/m)")
      ->capture_default_str()
      ->check(kPositive);
  cmd->add_option("--contact-impedance", args->options.contact_impedance, "contact impedance z_c")
      ->capture_default_str()
      ->check(kPositive);
  cmd->add_option("--out", args->out, "HDF5 file to write")->required();
  cmd->add_flag("--quiet", args->quiet, "no progress output");
  add_protocol_options(*cmd, args->protocol);
  add_variation_options(*cmd, args->options.variation);
  add_shard_option(*cmd, args->options.shard_index, args->options.shard_count);
  return [args] {
    args->options.density = parse_density(args->density);
    if (!args->mesh.empty()) {
      args->options.sensor_mesh = std::make_shared<const Mesh>(read_msh_file(args->mesh));
      args->options.sensor_source = std::filesystem::path(args->mesh).filename().string();
    }
    args->options.protocol = load_protocol(
        args->protocol, args->options.sensor_mesh ? args->options.sensor_mesh->num_electrodes()
                                                  : args->options.electrodes);
    const std::string mesh_label =
        args->mesh.empty() ? args->density : args->mesh + " refined once";
    if (world().parallel()) {
      if (args->options.shard_count != 1)
        throw InputError("--shard", "", "under mpirun the ranks are the shards: leave it out");
      return simulate_by_rank(args->options, mesh_label, args->out, args->quiet, world());
    }
    simulate_to(args->options, mesh_label, args->out, args->quiet);
  };
}

}  // namespace eitbench::cli
