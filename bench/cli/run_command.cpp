// eitbench run: the main job. Data, every reconstructor, the learned one trained without and with
// augmentation, all scored at every SNR, the data-efficiency sweep, and the report.
#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <memory>

#include "commands.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/report/report.h"
#include "eitbench/bench/run/benchmark_run.h"
#include "eitbench/bench/support/version.h"
#include "eitbench/jacobian/error.h"
#include "options.h"

namespace eitbench::cli {

std::function<void()> add_run_command(CLI::App& app) {
  struct Args {
    std::string preset = "quick", data, reference, out, device, sensor, mesh;
    std::uint64_t seed = 1;
    int threads = 2, electrodes = 16, epochs = 0, patience = -1;
    double learning_rate = 0;
    std::vector<std::string> methods, augments;
    ProtocolChoice protocol;
    bool resume = false, quiet = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "run",
      "The benchmark: every reconstructor on one data set, scored at every SNR, with a "
      "report");
  cmd->add_option("--preset", args->preset,
                  "quick (about 20 min on 2 cores) | standard | paper (the paper's protocol; GPU "
                  "advised, resumable) | tiny (seconds, for tests)")
      ->capture_default_str()
      ->check(CLI::IsMember({"tiny", "quick", "standard", "paper"}));
  cmd->add_option("--data", args->data,
                  "your data set instead of the simulated one: an eitbench HDF5 set with labels "
                  "and splits, or measured frames (with --reference) to rank methods on");
  cmd->add_option("--reference", args->reference, "measured frames: the empty sensor's frame");
  cmd->add_option("--sensor", args->sensor,
                  "a calibrated sensor file (eitbench calibrate): the model-based methods' "
                  "contact impedances, current and background conductivity");
  cmd->add_option("--mesh", args->mesh,
                  "a sensor of any shape: Gmsh mesh with electrode_0.. groups (eitbench mesh "
                  "--shape makes one). The preset's set is simulated on it, every method "
                  "reconstructs on it, and the learned model augments by its symmetry group")
      ->excludes("--data");
  cmd->add_option("--electrodes", args->electrodes, "electrodes of measured frames (--reference)")
      ->capture_default_str()
      ->check(CLI::Range(4, 256));
  cmd->add_option("--out", args->out, "output folder (default out/<preset>)");
  cmd->add_option("--seed", args->seed, "seed of the data, noise and training")
      ->capture_default_str();
  cmd->add_flag("--resume", args->resume,
                "reuse what an interrupted run in --out finished (data, methods, models, "
                "checkpoints) when it was made for the same data and options: another data set "
                "in --out stops the run, a stage made with other options is made again");
  cmd->add_option("--methods", args->methods, "model-based methods (default: all six)")
      ->delimiter(',')
      ->check(CLI::IsMember(model_based_method_names()));
  cmd->add_option("--augment", args->augments,
                  "augmentations of the learned reconstructor (default: the preset's; quick: "
                  "none,d16,paper, the others none,rotations,d16,paper; with --mesh none,group: "
                  "group is the sensor's whole symmetry group)")
      ->delimiter(',')
      ->check(CLI::IsMember({"none", "rotations", "d16", "paper", "mirror", "group"}));
  cmd->add_option("--epochs", args->epochs,
                  "each learned model's training budget in epochs, an upper bound: training stops "
                  "earlier when validation stops improving (default: the preset's)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--lr", args->learning_rate,
                  "the learning rate schedule's peak (default: the preset's, 1e-2 for the small "
                  "model, 1e-3 for the paper model)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--patience", args->patience,
                  "validations without a 0.5 % improvement before training stops (default 5; 0: "
                  "train to the budget)")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--device", args->device, "auto | cpu | cuda (default: the preset's)")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--threads", args->threads, "LibTorch threads")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("--quiet", args->quiet, "no progress output");
  add_protocol_options(*cmd, args->protocol);
  return [args] {
    RunConfig c = RunConfig::for_preset(args->preset);
    c.data = args->data;
    c.reference = args->reference;
    c.sensor = args->sensor;
    c.mesh_file = args->mesh;
    c.electrodes = args->electrodes;
    c.protocol = args->protocol.spec;
    c.magnitude = args->protocol.magnitude;
    c.out = args->out.empty() ? "out/" + args->preset : args->out;
    c.seed = args->seed;
    c.resume = args->resume;
    c.quiet = args->quiet;
    c.threads = args->threads;
    if (!args->methods.empty()) c.methods = args->methods;
    if (!args->augments.empty()) c.augments = args->augments, c.augments_chosen = true;
    if (args->epochs > 0) c.epochs = args->epochs;
    if (args->learning_rate > 0) c.learning_rate = args->learning_rate;
    if (args->patience >= 0) c.patience = args->patience;
    if (!args->device.empty()) c.device = args->device;
    if (!args->data.empty() && !args->reference.empty() && args->data == args->reference)
      throw InputError("--reference", "", "is the same file as --data");
    if (!c.quiet)
      fmt::print("{} run --preset {}: output in {}/\n", program_version(), c.preset, c.out);
    const auto t0 = std::chrono::steady_clock::now();
    const RunResults results = run_benchmark(c);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    fmt::print("\n{}\n{}\n\nwrote {}/report.md, results.json, results.csv{} in {:.0f} s\n",
               summary_table(results), results.recommendation, c.out,
               can_draw_figures() ? " and the figures" : " (no figures: this build draws none)",
               seconds);
  };
}

}  // namespace eitbench::cli
