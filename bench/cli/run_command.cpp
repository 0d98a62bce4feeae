// eitbench run: the main job. Data, every reconstructor, the learned one trained without and with
// augmentation, all scored at every SNR, the data-efficiency sweep, and the report.
#include <fmt/core.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>

#include "commands.h"
#include "eitbench/bench/io/folder_lock.h"
#include "eitbench/bench/ktc/ktc_method.h"
#include "eitbench/bench/ktc/ktc_report.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/report/report.h"
#include "eitbench/bench/run/benchmark_run.h"
#include "eitbench/bench/run/shards.h"
#include "eitbench/bench/support/timing.h"
#include "eitbench/bench/support/version.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/learned/runtime.h"
#include "eitbench/learned/schedule.h"
#include "options.h"
#include "world.h"

namespace eitbench::cli {

namespace {

// "a,b,c" -> {"a", "b", "c"}; every comma separates, so "a," ends with an empty item.
std::vector<std::string> comma_items(const std::string& text) {
  std::vector<std::string> items;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    items.push_back(text.substr(start, comma - start));
    start = comma + 1;
  }
  return items;
}

// A whole decimal number, or none for anything else ("", "1.5", "2x").
std::optional<int> whole_number(const std::string& item) {
  std::size_t used = 0;
  int n = 0;
  try {
    n = std::stoi(item, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != item.size() || item.empty()) return std::nullopt;
  return n;
}

// --sweep: "none", or training-set sizes in ascending order, each at least 2.
std::vector<int> parse_sweep(const std::string& text) {
  if (text == "none") return {};
  if (text.empty()) throw InputError("--sweep", "", "needs sizes, or none");
  std::vector<int> sizes;
  for (const std::string& item : comma_items(text)) {
    const std::optional<int> n = whole_number(item);
    if (!n || *n < 2 || *n > 100000000)
      throw InputError("--sweep", "", "'" + item + "' is not a training-set size (2 or more)");
    if (!sizes.empty() && *n <= sizes.back())
      throw InputError("--sweep", "", "sizes must ascend, each once");
    sizes.push_back(*n);
  }
  return sizes;
}

// "0,10,30,100,all" -> {0, 10, 30, 100, -1}: sizes of 0 or at least 3 (two to train, one to
// stop on), ascending, each once.
std::vector<int> parse_finetune(const std::string& text) {
  std::vector<int> sizes;
  if (text.empty()) return sizes;
  for (const std::string& item : comma_items(text)) {
    int n = -1;
    if (item != "all") {
      const std::optional<int> number = whole_number(item);
      if (!number || *number < 0 || *number == 1 || *number == 2)
        throw InputError("--finetune", "",
                         "'" + item + "' is not a number of presses: 0, 3 or more, or all");
      n = *number;
    }
    if (!sizes.empty() && (sizes.back() < 0 || (n >= 0 && n <= sizes.back())))
      throw InputError("--finetune", "", "sizes must ascend, each once, all last");
    sizes.push_back(n);
  }
  return sizes;
}

void check_press_sets(const RunConfig& c) {
  if (c.measured.empty() && (!c.press_calibration.empty() || !c.finetune.empty()))
    throw InputError(c.press_calibration.empty() ? "--finetune" : "--calibration", "",
                     "goes with --measured (the real presses to score)");
  if (c.measured.empty()) return;
  if (c.press_calibration.empty())
    throw InputError("--measured", "",
                     "needs --calibration: a labelled press set of the same sensor to tune on");
  std::error_code error;
  if (std::filesystem::equivalent(c.measured, c.press_calibration, error))
    throw InputError("--calibration", "",
                     "is the measured set: tune on another recording, never on the scored presses");
  if (c.mesh_file.size())
    throw InputError("--measured", "", "is scored on the disk; not with --mesh");
}

// The flags given, as a shard records them for merge: every option but --shard, --out and
// --resume, with its values as parsed (lists split at their commas; a flag by its name).
std::vector<std::string> given_arguments(const CLI::App& cmd) {
  std::vector<std::string> out;
  for (const CLI::Option* o : cmd.get_options()) {
    const std::string name = o->get_name();
    if (o->count() == 0 || name == "--shard" || name == "--out" || name == "--resume" ||
        name == "--merge-shards")
      continue;
    out.push_back(name);
    if (o->get_expected_min() > 0)
      for (const std::string& value : o->results()) out.push_back(value);
  }
  return out;
}

// The whole run, its summary and where it wrote.
void run_and_report(const RunConfig& c) {
  const auto t0 = std::chrono::steady_clock::now();
  const RunResults results = run_benchmark(c);
  const double seconds = seconds_since(t0);
  fmt::print("\n{}\n{}\n\nwrote {}/report.md, results.json, results.csv{} in {:.0f} s\n",
             summary_table(results), results.recommendation, c.out,
             can_draw_figures() ? " and the figures" : " (no figures: this build draws none)",
             seconds);
}

void run_one_shard(const RunConfig& c) {
  const auto t0 = std::chrono::steady_clock::now();
  run_benchmark(c);
  fmt::print("shard {} of {} finished in {:.0f} s ({}); when every shard has: eitbench merge {}\n",
             c.shard_index, c.shard_count, seconds_since(t0),
             run_shard_folder(c.out, c.shard_index, c.shard_count).string(), c.out);
}

// Under mpirun (docs/scaling.md): rank K of N makes shard K, then rank 0 joins them (the whole
// run, resumed from the shards' stages). Every rank reaches the collective whatever happened to
// it, so one rank's failure ends every rank; each shard's folder stays, for --resume.
void run_by_rank(RunConfig c, World w) {
  c.shard_index = w.rank, c.shard_count = w.size;
  const bool quiet = c.quiet;
  c.quiet = quiet || w.rank != 0;
  on_every_rank([&] { run_benchmark(c); }, "rerun with --resume to finish the run");
  if (w.rank != 0) return;
  c.shard_index = 0, c.shard_count = 1, c.resume = true, c.quiet = quiet, c.merge_shards = true;
  run_and_report(c);
}

// KTC2023 (--ktc): every model-based method on the challenge's training samples and levels.
struct KtcArgs {
  std::string folder, density = "medium";
  std::vector<int> levels;
  int pixels = 64;
  double coverage = KtcTankOptions().electrode_coverage;
  KtcNoise noise;
  std::vector<double> noise_sweep = KtcRunOptions().noise_sweep;
  int tuning_tanks = KtcRunOptions().tuning_tanks;
  double tuning_noise = KtcRunOptions().tuning_noise;
  std::vector<std::string> simulation_tuned = KtcRunOptions().simulation_tuned;
  KtcLearnedOptions learned;  // tanks and steps here; arms, doublings and patience from run's
};

void add_ktc_options(CLI::App& cmd, KtcArgs& k) {
  const char* group = "KTC2023 (--ktc)";
  cmd.add_option("--ktc", k.folder,
                 "rank the model-based methods and learned models on KTC2023's training samples "
                 "instead: a folder of "
                 "ref.mat, dataN.mat and trueN.mat (docs/ktc.md)")
      ->group(group);
  cmd.add_option("--levels", k.levels, "with --ktc: the difficulty levels (default 1 ... 7)")
      ->delimiter(',')
      ->check(CLI::Range(1, 7))
      ->group(group);
  cmd.add_option("--electrode-coverage", k.coverage, "with --ktc: the rim's share under electrodes")
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--density", k.density, "with --ktc: the tank's mesh, coarse | medium | fine")
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--pixels", k.pixels, "with --ktc: the reconstructions' grid, pixels a side")
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--noise-relative", k.noise.relative,
                 "with --ktc: the data term's noise, this share of each reference value ...")
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--noise-floor", k.noise.floor, "... and this share of the largest")
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--noise-sweep", k.noise_sweep,
                 "with --ktc: the noise models (shares of each reference value) each method is "
                 "tuned over, as its weight is; GREIT (which they do not change) and the learned "
                 "rows take --noise-relative (given alone, it sets this too)")
      ->delimiter(',')
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--tuning-tanks", k.tuning_tanks,
                 "with --ktc: simulated tanks (labelled, drawn from --seed) that the methods of "
                 "--tune-on-simulation are tuned on too, every sample then held out (0: none; "
                 "at most 500, about 3 MB each)")
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--tuning-noise", k.tuning_noise,
                 "with --ktc: each tuning tank value's noise, V (0, the default: the reference's "
                 "measured noise; more stands in for the real tank's model error, which the run "
                 "prints: each sample's model misfit and the noise it implies with each sample "
                 "held out)")
      ->capture_default_str()
      ->group(group);
  cmd.add_option("--tune-on-simulation", k.simulation_tuned,
                 "with --ktc: the methods tuned on the simulated tanks as well as on the samples "
                 "(default the one-step methods: an iterative one costs its seconds a frame for "
                 "every tank, weight and level)")
      ->delimiter(',')
      ->default_str([] {
        std::string names;
        for (const auto& m : KtcRunOptions().simulation_tuned)
          names += (names.empty() ? "" : ",") + m;
        return names;
      }())
      ->group(group);
  cmd.add_option("--ktc-tanks", k.learned.tanks,
                 "with --ktc: simulated tanks the learned models (--augment none,group) train, "
                 "validate and test on (0: no learned rows)")
      ->capture_default_str()
      ->check(CLI::Range(0, 200000))
      ->group(group);
  cmd.add_option("--ktc-steps", k.learned.network.steps,
                 "with --ktc: each learned model's budget in optimiser steps (batch 64), before "
                 "the doublings (--doublings, default 4 with --ktc)")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000000))
      ->group(group);
  cmd.add_option("--ktc-learned", k.learned.networks,
                 "with --ktc: the learned networks, dnn (from the frame) and dnn-post (from a "
                 "one-step image, as the challenge's winners did)")
      ->delimiter(',')
      ->default_str("dnn,dnn-post")
      ->group(group);
  cmd.add_option("--one-step-lambda", k.learned.one_step.lambda,
                 "with --ktc: dnn-post's one-step image, NOSER at this weight (relative; fixed "
                 "beforehand, not tuned on the samples)")
      ->capture_default_str()
      ->group(group);
}

// The run command's own flags that a KTC run also reads (the learned rows').
struct KtcRunFlags {
  std::vector<std::string> methods, augments;
  std::string out;
  int doublings = -1, patience = -1, threads = 2;
  double doubling_tolerance = -1;
  bool quiet = false;
  std::string device;      // empty: the CPU
  std::uint64_t seed = 1;  // the simulated tanks' and the learned models'
};

void run_ktc_benchmark(KtcArgs k, const KtcRunFlags& f, const CLI::App& cmd) {
  for (const char* other : {"--data", "--reference", "--measured", "--mesh", "--preset", "--sensor",
                            "--shard", "--protocol", "--magnitude", "--epochs", "--lr", "--decay"})
    if (cmd.count(other) > 0)
      throw InputError("--ktc", "",
                       std::string("ranks the methods on KTC's data: leave out ") + other);
  if (world().parallel()) throw InputError("--ktc", "", "runs as one process: leave out mpirun");
  const std::vector<std::string>& methods = f.methods;
  const std::string& out = f.out;
  const bool quiet = f.quiet;
  if (!f.augments.empty()) k.learned.arms = f.augments;
  if (k.learned.tanks == 0) k.learned.arms.clear();
  if (f.doublings >= 0) k.learned.rule.max_doublings = f.doublings;
  if (f.doubling_tolerance >= 0) k.learned.rule.tolerance = f.doubling_tolerance;
  if (f.patience >= 0) k.learned.network.patience = f.patience;
  if (!f.device.empty()) k.learned.network.device = f.device;
  k.learned.network.seed = f.seed;
  if (!k.learned.arms.empty()) set_torch_threads(f.threads);
  KtcRunOptions o;
  o.data = k.folder;
  o.out = out.empty() ? "out/ktc" : out;
  if (!methods.empty()) o.methods = methods;
  if (!k.levels.empty()) o.levels = k.levels;
  o.tank.electrode_coverage = k.coverage;
  o.tank.density = parse_density(k.density);
  o.noise = k.noise;
  o.noise_sweep = cmd.count("--noise-relative") > 0 && cmd.count("--noise-sweep") == 0
                      ? std::vector<double>{k.noise.relative}
                      : k.noise_sweep;
  o.grid = k.pixels;
  o.tuning_tanks = k.tuning_tanks;
  o.tuning_noise = k.tuning_noise;
  o.tuning_seed = f.seed;
  o.simulation_tuned = k.simulation_tuned;
  if (cmd.count("--tune-on-simulation") > 0) {  // asked for: each method is tuned so, or refused
    if (o.tuning_tanks == 0)
      throw InputError("--tune-on-simulation", "", "needs tanks to tune on: --tuning-tanks 0");
    for (const std::string& m : o.simulation_tuned)
      if (std::find(o.methods.begin(), o.methods.end(), m) == o.methods.end())
        throw InputError("--tune-on-simulation", "",
                         "names " + m + ", which the run does not rank (--methods)");
  }
  // The tanks' noise asked for where no tanks are drawn would be dropped without a word.
  if (cmd.count("--tuning-noise") > 0 && !o.draws_tuning_tanks())
    throw InputError("--tuning-noise", "",
                     "no method of --methods is tuned on simulated tanks (--tuning-tanks, "
                     "--tune-on-simulation)");
  k.learned.one_step_grid = k.pixels;
  o.learned = k.learned;
  o.quiet = quiet;
  const KtcInputs inputs = load_ktc_inputs(o);  // every file read and checked first
  if (std::filesystem::exists(o.out) && !std::filesystem::is_directory(o.out))
    throw InputError(o.out, "", "is a file; --out takes a folder");
  std::error_code error;
  std::filesystem::create_directories(o.out, error);
  if (error) throw InputError(o.out, "", "cannot create the folder: " + error.message());
  const FolderLock lock(o.out);
  if (!quiet) fmt::print("{} run --ktc {}: output in {}/\n", program_version(), o.data, o.out);
  const auto t0 = std::chrono::steady_clock::now();
  const KtcRunResults results = run_ktc(o, inputs);
  write_ktc_run(results);
  if (quiet) return;
  fmt::print(
      "\n| method | total of 21, held out | tuned on simulation | samples and tanks | Otsu only | "
      "setting | ms a frame |\n");
  auto total_or_dash = [](const std::vector<std::vector<double>>& table) {
    return table.empty() ? std::string("—") : fmt::format("{:.2f}", ktc_total(table));
  };
  for (const auto& m : results.methods)
    fmt::print("| {} | {:.2f} | {} | {} | {:.2f} | lambda {:.3g}, {} | {:.1f} |\n", m.method,
               ktc_total(m.held_out), total_or_dash(m.tuned_on_simulation),
               total_or_dash(m.tuned_jointly), ktc_total(m.held_out_otsu), m.best.lambda,
               m.best.rule.to_string(), m.median_ms);
  for (const auto& a : results.learned.arms)
    fmt::print("| {} {} | {:.2f} | — | — | — | trained in simulation ({}, {} steps) | {:.1f} |\n",
               a.network, a.arm, ktc_total(a.scores), to_string(a.end), a.steps, a.median_ms);
  fmt::print("\nwrote {}/report.md and results.json in {:.0f} s\n", o.out, seconds_since(t0));
}

}  // namespace

std::function<void()> add_run_command(CLI::App& app) {
  struct Args {
    std::string preset = "quick", data, reference, out, device, sensor, mesh, measured,
                press_calibration, finetune, sweep;
    double radius_mm = 0;
    std::uint64_t seed = 1;
    int threads = 2, electrodes = 16, epochs = 0, patience = -1, doublings = -1;
    double doubling_tolerance = -1;
    long long finetune_steps = RunConfig().finetune_steps;
    double learning_rate = 0, decay = -1;
    std::vector<std::string> methods, augments;
    ProtocolChoice protocol;
    SimulationVariation variation;
    bool resume = false, quiet = false, merge_shards = false;
    int shard_index = 0, shard_count = 1;
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
  cmd->add_option("--measured", args->measured,
                  "real presses to score every method on: a press set (import --touches) of the "
                  "sensor the preset is simulated for, read on its protocol")
      ->excludes("--data")
      ->excludes("--reference");
  cmd->add_option("--calibration", args->press_calibration,
                  "with --measured: a labelled press set of the same sensor (another recording) "
                  "that tunes the methods, fits the fingerprint and fine-tunes the learned model; "
                  "nothing is tuned on --measured");
  cmd->add_option(
      "--finetune", args->finetune,
      "with --measured: numbers of the calibration set's first presses to fine-tune the "
      "learned model on, with and without d16 augmentation, beside the network trained "
      "on them from scratch (e.g. 0,10,30,100,300,all; 0: as trained in simulation)");
  cmd->add_option("--sweep", args->sweep,
                  "the data-efficiency sweep's training-set sizes, comma-separated (default: the "
                  "preset's, e.g. quick 500,2000), or none to leave it out");
  cmd->add_option("--finetune-steps", args->finetune_steps,
                  "each fine-tuning's budget in optimiser steps (early stopping ends it sooner)")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000000));
  cmd->add_option("--radius-mm", args->radius_mm,
                  "the sensor's radius in millimetres: the report gives the press errors in mm too")
      ->check(CLI::PositiveNumber);
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
  // The defaults named from where they are set, so that the help follows the build (no shape fit
  // without Ceres) and the KTC list.
  cmd->add_option("--methods", args->methods,
                  fmt::format("model-based methods, comma-separated (default: {}; with --ktc: {})",
                              fmt::join(RunConfig::for_preset("quick").methods, ", "),
                              fmt::join(ktc_method_names(), ", ")))
      ->delimiter(',')
      ->check(CLI::IsMember(model_based_method_names()));
  cmd->add_option("--augment", args->augments,
                  "augmentations of the learned reconstructor (default: the preset's; quick: "
                  "none,d16, the others none,rotations,d16,paper; with --mesh or --ktc "
                  "none,group: group is the sensor's whole symmetry group)")
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
  cmd->add_option("--decay", args->decay,
                  "where the learning rate's cosine reaches its floor, as a fraction of the "
                  "budget, in the training on the simulated set (default: the preset's, 0.9 "
                  "quick, 0.6 otherwise; a fine-tuning on presses keeps 0.6)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--doublings", args->doublings,
                  "after the budget, continue each learned model from its best over as many "
                  "steps again while the last doubling lowered its best validation loss by more "
                  "than --doubling-tolerance, at most this many times (default: the preset's; "
                  "tiny and quick 0, standard and paper 3, --ktc 4; docs/learned.md)")
      ->check(CLI::Range(0, 20));
  cmd->add_option("--doubling-tolerance", args->doubling_tolerance,
                  "the relative drop of the best validation loss a doubling must bring for another "
                  "(default 0.01)")
      ->check(CLI::Range(0.0, 0.99));
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
  add_variation_options(*cmd, args->variation);
  add_shard_option(*cmd, args->shard_index, args->shard_count);
  auto ktc = std::make_shared<KtcArgs>();
  add_ktc_options(*cmd, *ktc);
  // What `eitbench merge RUN` runs: the shards' own flags with this one (no help: merge's job).
  cmd->add_flag("--merge-shards", args->merge_shards)->group("");
  return [args, cmd, ktc] {
    if (cmd->count("--ktc") > 0)
      return run_ktc_benchmark(
          *ktc,
          {args->methods, args->augments, args->out, args->doublings, args->patience, args->threads,
           args->doubling_tolerance, args->quiet, args->device, args->seed},
          *cmd);
    for (const char* flag :
         {"--levels", "--electrode-coverage", "--density", "--pixels", "--noise-relative",
          "--noise-floor", "--noise-sweep", "--tuning-tanks", "--tuning-noise",
          "--tune-on-simulation", "--ktc-tanks", "--ktc-steps"})
      if (cmd->count(flag) > 0) throw InputError(flag, "", "goes with --ktc");
    RunConfig c = RunConfig::for_preset(args->preset);
    c.data = args->data;
    c.reference = args->reference;
    c.sensor = args->sensor;
    c.mesh_file = args->mesh;
    c.electrodes = args->electrodes;
    c.protocol = args->protocol.spec;
    c.magnitude = args->protocol.magnitude;
    c.variation = args->variation;
    c.variation.validate();
    c.out = args->out.empty() ? "out/" + args->preset : args->out;
    c.seed = args->seed;
    c.measured = args->measured;
    c.press_calibration = args->press_calibration;
    c.finetune = parse_finetune(args->finetune);
    c.finetune_steps = args->finetune_steps;
    if (!args->sweep.empty()) c.efficiency_sizes = parse_sweep(args->sweep);
    c.radius_mm = args->radius_mm;
    check_press_sets(c);
    c.resume = args->resume;
    c.quiet = args->quiet;
    c.threads = args->threads;
    if (!args->methods.empty()) c.methods = args->methods;
    if (!args->augments.empty()) c.augments = args->augments, c.augments_chosen = true;
    if (args->epochs > 0) c.epochs = args->epochs;
    if (args->learning_rate > 0) c.learning_rate = args->learning_rate;
    if (args->decay >= 0) c.decay = args->decay;
    if (const double warmup = ScheduleOptions().warmup_fraction; c.decay < warmup)
      throw InputError("--decay", "",
                       fmt::format("must be at least the warm-up's {:g} of the budget", warmup));
    if (args->patience >= 0) c.patience = args->patience;
    if (args->doublings >= 0) c.budget_rule.max_doublings = args->doublings;
    if (args->doubling_tolerance >= 0) c.budget_rule.tolerance = args->doubling_tolerance;
    if (!args->device.empty()) c.device = args->device;
    if (!args->data.empty() && !args->reference.empty() && args->data == args->reference)
      throw InputError("--reference", "", "is the same file as --data");
    c.shard_index = args->shard_index, c.shard_count = args->shard_count;
    c.merge_shards = args->merge_shards;
    if (c.merge_shards && c.shard_count != 1)
      throw InputError("--shard", "", "a merge joins every shard: leave it out");
    c.arguments = given_arguments(*cmd);
    if (world().parallel()) {
      if (c.shard_count != 1)
        throw InputError("--shard", "", "under mpirun the ranks are the shards: leave it out");
      return run_by_rank(c, world());
    }
    if (!c.quiet)
      fmt::print("{} run --preset {}: output in {}/\n", program_version(), c.preset, c.out);
    if (c.shard_count > 1) return run_one_shard(c);
    run_and_report(c);
  };
}

}  // namespace eitbench::cli
