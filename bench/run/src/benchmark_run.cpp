// The benchmark run: the stages of stages.h in order, then the results store and the report drawn
// from it (so `eitbench report` draws the same report from a finished run).
#include "eitbench/bench/run/benchmark_run.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "eitbench/bench/data/sensor.h"
#include "eitbench/bench/io/folder_lock.h"
#include "eitbench/bench/methods/touches.h"
#include "eitbench/bench/report/report.h"
#include "eitbench/bench/report/run_store.h"
#include "eitbench/bench/run/shards.h"
#include "eitbench/bench/support/machine.h"
#include "eitbench/bench/support/timing.h"
#include "eitbench/bench/support/version.h"
#include "eitbench/jacobian/error.h"
#include "stages.h"

namespace eitbench {
namespace fs = std::filesystem;

namespace run {

void Context::say(const std::string& line) const {
  if (!config.quiet) fmt::print("{}\n", line), std::fflush(stdout);
}

namespace {

// LibTorch's threads, fixed whatever the launcher's environment (before anything is written: the
// environment may refuse them). A layout that makes them wait for a core is said even under
// --quiet: the run is then far slower, not wrong.
void fix_threads(const RunConfig& config) {
  set_torch_threads(config.threads);
  const std::string warning = thread_layout().warning();
  if (!warning.empty()) fmt::print(stderr, "warning: {}\n", warning);
}

fs::path output_folder(const RunConfig& config) {
  const fs::path out(config.out);
  if (fs::exists(out) && !fs::is_directory(out))
    throw InputError(config.out, "", "is a file; --out takes a folder");
  std::error_code error;
  fs::create_directories(out / "models", error);
  if (error) throw InputError(config.out, "", "cannot create the folder: " + error.message());
  return out;
}

// How the run was made, for results.json and the report.
std::map<std::string, std::string> describe_run(const RunConfig& config, const RunData& data,
                                                const Reconstruction& reconstruction,
                                                const LearnedSetup& learned, long long parameters,
                                                double total_s) {
  std::map<std::string, std::string> c;
  c["preset"] = config.preset;
  c["seed"] = std::to_string(config.seed);
  c["data"] = data.data_path;
  c["data_provenance"] =
      data.data.simulation_mesh + " (" + data.data.preset + ", " + data.data.program + ")";
  c["test_frames"] = std::to_string(data.test.frames.rows());
  c["training_samples"] = std::to_string(data.source.indices(Split::train).size());
  c["validation_frames"] = std::to_string(data.validation.frames.rows());
  if (has_sensor_mesh(data.sensor())) {
    const auto sensor = shaped_sensor_of(data.sensor());
    c["reconstruction_mesh"] = fmt::format(
        "the sensor's own mesh ({} triangles, {} electrodes; images {} x {} over its "
        "bounding box, {} pixels inside)",
        reconstruction.mesh.num_triangles(), data.sensor().electrodes, reconstruction.grid.size(),
        reconstruction.grid.size(), reconstruction.grid.num_inside());
    c["sensor_group"] =
        sensor->group.order() > 1
            ? fmt::format(
                  "{}, {} elements, found from the mesh: 'dnn group' trains on every "
                  "frame moved by each element (x{})",
                  sensor->group.name(), sensor->group.order(), sensor->group.order())
            : "trivial: the sensor has no symmetry, so the learned model is not augmented";
  } else {
    c["reconstruction_mesh"] =
        fmt::format("disk L={} {} ({} triangles)", data.data.electrodes, to_string(config.mesh),
                    reconstruction.mesh.num_triangles());
  }
  const MeasurementProtocol protocol = measurement_protocol(data.sensor());
  c["protocol"] = fmt::format(
      "{}: {} channels, {} inputs{}{}", protocol.name(), protocol.size(), protocol.input_size(),
      protocol.reciprocal() ? " (reciprocity-reduced)" : " (not reciprocal: every channel)",
      protocol.magnitude() ? "; magnitudes |v|, model frames and Jacobian those of |v|" : "");
  if (protocol.magnitude() && reconstruction.problem) {  // |v|'s sign is unsure near v = 0
    const auto& model = *reconstruction.problem->model;
    const auto weak = weak_channels(model.inputs(Eigen::VectorXd::Constant(
        model.mesh().num_triangles(), reconstruction.problem->background)));
    c["protocol"] += fmt::format(
        "; {} input{} with |v0| under 1e-3 of the largest (an unsure sign: drop them from a CSV "
        "protocol to weight them out)",
        weak.size(), weak.size() == 1 ? "" : "s");
  }
  c["background"] = fmt::format("{:g}", data.sensor().background);
  if (!data.own_training) c["calibration"] = describe(data.calibration);
  std::string snrs;
  for (double v : data.snrs) snrs += (snrs.empty() ? "" : " ") + snr_label(v);
  c["snrs_db"] = snrs;
  c["model"] = fmt::format("{} ({} parameters, {:.1f} MFLOP a frame)", config.model, parameters,
                           forward_flops(learned.network) / 1e6);
  c["training"] = fmt::format(
      "at most {} epochs, batch {}, Adam peak lr {:g} ({} schedule, at its floor after {:g} of "
      "the budget), validation every {} samples, early stopping after {} without a {:g} "
      "improvement, on-the-fly augmentation, device {}",
      config.epochs, config.batch, config.learning_rate, config.schedule, config.decay,
      config.validate_every, config.patience, config.min_improvement, learned.training.device);
  if (learned.gemm_flops > 0)
    c["gemm_peak"] = fmt::format("{:.0f} GFLOP/s (float32 2048 x 2048 matrix product, {} threads)",
                                 learned.gemm_flops / 1e9, config.threads);
  if (!config.efficiency_sizes.empty() && !has_sensor_mesh(data.sensor())) {
    const auto sizes = sweep_sizes(config.efficiency_sizes,
                                   static_cast<int>(data.source.indices(Split::train).size()));
    c["efficiency"] = fmt::format(
        "sizes {} to {}: none and d16 to convergence, d16 at none's steps (equal compute)",
        sizes.front(), sizes.back());
  }
  c["hyperparameters"] =
      fmt::format("validation CC at each SNR ({} validation frames; tv and gn sweep {})",
                  data.validation.frames.rows(), config.sweep_frames);
  if (scores_touches(data)) {
    const TouchOptions touch;
    std::string candidates;
    for (double t : touch.thresholds)
      candidates += fmt::format("{}{:g}", candidates.empty() ? "" : ", ", t);
    c["touch_metrics"] = fmt::format(
        "blobs at a threshold (x the image's in-disk maximum) chosen per method and SNR from "
        "{{{}}} "
        "by count accuracy, then median centre error, on {} validation frames; blobs under {:g} "
        "R^2 dropped; matched within {:g} R",
        candidates,
        std::min<Eigen::Index>(config.touch_validation_frames, data.validation.frames.rows()),
        touch.min_area, touch.gate);
  }
  c["latency"] = fmt::format("the first {} test frames one at a time, wall clock, {} threads",
                             config.timed_frames, config.threads);
  // The learned rows are scored and timed on the training device (learned_stage.cpp).
  if (learned.training.device != "cpu") c["learned_device"] = learned.training.device;
  if (!config.measured.empty()) {
    c["measured"] = config.measured;
    c["press_calibration"] = config.press_calibration;
    if (config.radius_mm > 0) c["radius_mm"] = fmt::format("{:g}", config.radius_mm);
    c["press_scores"] = fmt::format(
        "centre error of each press of the measured set: its strongest blob or the centroid of "
        "every pixel above the threshold (the rule and the threshold chosen on the calibration "
        "presses; the blob at 0.5 for models trained on presses and for rows without labels) "
        "or the centre when none; model-based methods tuned in simulation (validation CC) and on "
        "the calibration presses (mean centre error; tv, gn and the shape fits on the first {}), "
        "the one-step methods also by GCV on the calibration frames; fine-tuning: {} steps at "
        "most, a tenth of the peak rate, every fifth press held out for early stopping",
        8 * config.sweep_frames, config.finetune_steps);
  }
  c["total_seconds"] = fmt::format("{:.1f}", total_s);
  return c;
}

// The learned models to train: the configuration's augmentations on the disk; on a sensor of
// another shape none and its whole group ("group"), or none alone when the group is trivial, unless
// the user asked for others (which the group then filters: rotations are its rotations).
std::vector<std::string> learned_augments(const Context& context, const RunData& data) {
  const RunConfig& config = context.config;
  const MeasurementProtocol protocol = measurement_protocol(data.source);
  if (!has_sensor_mesh(data.source) && is_adjacent(protocol)) return config.augments;
  if (!has_sensor_mesh(data.source)) {  // another protocol: the paper's variant is the map's only
    std::vector<std::string> out;
    for (const std::string& a : config.augments) {
      if (a == "paper" && config.augments_chosen)
        throw InputError("--augment", "",
                         "paper is defined on the adjacent protocol's map; the " + protocol.name() +
                             " protocol augments by none, rotations, mirror or d16");
      if (a != "paper") out.push_back(a);
    }
    return out;
  }
  const auto sensor = shaped_sensor_of(data.source);
  std::vector<std::string> out;
  for (const std::string& a :
       config.augments_chosen ? config.augments : std::vector<std::string>{"none", "group"}) {
    if (a == "paper" || a == "d16")
      throw InputError("--augment", "",
                       a + " is the disk's; a sensor of another shape augments by its own group "
                           "(group, rotations, mirror or none)");
    if (a != "none" && sensor->group.order() == 1) continue;
    out.push_back(a);
  }
  if (sensor->group.order() > 1)
    context.say(fmt::format(
        "sensor: symmetry group {} ({} elements): the learned model 'group' augments by {}",
        sensor->group.name(), sensor->group.order(), sensor->group.order()));
  else
    context.say(
        "sensor: no symmetry (the trivial group): no augmentation, the learned model trains on "
        "the frames as they are");
  return out;
}

// The fingerprint of the whole run (results.json): everything its stages' provenances hold.
std::string run_fingerprint(const RunConfig& config, const RunData& data) {
  Provenance p = data.provenance;
  for (const auto& [key, value] : training_provenance(config, data)) p["training: " + key] = value;
  std::string list;
  for (const auto& m : config.methods) list += m + " ";
  p["methods"] = list;
  list.clear();
  for (const auto& a : config.augments) list += a + " ";
  p["augments"] = list;
  if (!config.mesh_file.empty()) p["sensor mesh"] = config.mesh_file;
  if (!config.measured.empty()) {
    p["scored presses"] = file_hash(config.measured);
    p["calibration presses"] = file_hash(config.press_calibration);
    list.clear();
    for (int n : config.finetune) list += std::to_string(n) + " ";
    p["finetune"] = list;
  }
  list.clear();
  for (int n : config.efficiency_sizes) list += std::to_string(n) + " ";
  p["efficiency sizes"] = list;
  return fingerprint(p);
}

// The float32 GEMM peak that training throughput is compared with (0 off the CPU), measured
// first: after the model-based stage (TBB and CHOLMOD's threads) the same product ran at half the
// speed.
double gemm_peak(const RunConfig& config) {
  if (resolve_device(config.device, "--device") != "cpu") return 0;
  const int n = 2048;
  return 2.0 * n * n * n / time_matmul(n, 3);
}

// A merge (docs/scaling.md): the shards' stages, models and data brought into `out`, and the
// fingerprint they were made for; InputError when a shard is missing, unfinished or foreign.
std::string gather_shards(const RunConfig& config) {
  const std::vector<RunShardRecord> shards = gather_run_shards(config.out);
  if (!config.quiet) fmt::print("{}: {}\n", config.out, describe_balance(shards));
  return shards.front().fingerprint;
}

// A merge makes the run the shards were made for, or none: another program, device or data set
// would make every stage again, silently.
void check_merge(const RunConfig& config, const RunData& data, const std::string& shards) {
  if (shards.empty() || run_fingerprint(config, data) == shards) return;
  throw InputError(config.out, "fingerprint",
                   "the shards were made for another run than this merge would make (another "
                   "program version, --device as resolved here, or data): merge where the shards "
                   "ran, with the same build");
}

Context context_for(const RunConfig& config, const fs::path& out) {
  return Context{config, out,
                 StageCache(out / "stages", config.resume, [&config](const std::string& line) {
                   if (!config.quiet) fmt::print("{}\n", line), std::fflush(stdout);
                 })};
}

// A shard's share of the run (docs/scaling.md): the units of work dealt round-robin in the run's
// order, each model-based method, each learned model and each sweep size below the whole training
// set. The sweep's whole-set size takes none's and d16's converged points from their main
// trainings and trains d16 for none's steps, so none, d16 and that size make one unit.
struct WorkUnit {
  std::string name;
  std::vector<std::string> methods, augments;
  std::vector<int> sizes;
};

std::vector<WorkUnit> shard_work(const RunConfig& c, const std::vector<std::string>& augments,
                                 int train_count, bool sweep) {
  std::vector<WorkUnit> units;
  for (const std::string& m : c.methods) units.push_back({m, {m}, {}, {}});
  const std::vector<int> sizes =
      sweep ? sweep_sizes(c.efficiency_sizes, train_count) : std::vector<int>();
  const bool whole = std::find(sizes.begin(), sizes.end(), train_count) != sizes.end();
  WorkUnit joint{
      "dnn none and d16 with the sweep at n=" + std::to_string(train_count), {}, {}, {train_count}};
  for (const std::string& a : augments)
    if (whole && (a == "none" || a == "d16"))
      joint.augments.push_back(a);
    else
      units.push_back({"dnn " + a, {}, {a}, {}});
  if (whole) units.push_back(joint);
  for (int n : sizes)
    if (n != train_count) units.push_back({"sweep n=" + std::to_string(n), {}, {}, {n}});
  std::vector<WorkUnit> mine;
  for (std::size_t u = c.shard_index; u < units.size(); u += c.shard_count)
    mine.push_back(units[u]);
  return mine;
}

// Shard K of N: its units' stages and models in <out>/shards/K-of-N/, then the record that it
// finished (removed first, so that a shard cut off is never taken for finished), with how long the
// set-up and each unit took.
RunResults run_shard(const RunConfig& whole) {
  const auto t_start = std::chrono::steady_clock::now();
  fix_threads(whole);
  RunConfig config = whole;
  config.out = run_shard_folder(whole.out, whole.shard_index, whole.shard_count).string();
  const fs::path out = output_folder(config);
  const FolderLock lock(out.string());
  fs::remove(out / "shard.json");
  const Context context = context_for(config, out);
  const double gemm_flops = gemm_peak(config);
  const RunData data = load_data(context);
  const Reconstruction reconstruction = set_up_reconstruction(context, data);
  const NoisyFrames noisy = noisy_copies(config, data);
  const std::vector<std::string> augments = learned_augments(context, data);
  LearnedSetup learned = learned_setup(config, data.source);
  learned.gemm_flops = gemm_flops;
  const int train_count = static_cast<int>(data.source.indices(Split::train).size());
  const std::vector<WorkUnit> work =
      shard_work(config, augments, train_count, !has_sensor_mesh(data.sensor()));
  RunShardRecord record;
  record.index = config.shard_index, record.count = config.shard_count;
  record.arguments = config.arguments, record.fingerprint = run_fingerprint(config, data);
  record.setup_seconds = seconds_since(t_start);
  std::string names;
  for (const WorkUnit& u : work) names += (names.empty() ? "" : "; ") + u.name;
  context.say(fmt::format("shard {} of {}: {}", config.shard_index, config.shard_count,
                          names.empty() ? "no units (more shards than units)" : names));
  RunResults results;
  for (const WorkUnit& unit : work) {
    const auto t0 = std::chrono::steady_clock::now();
    for (const std::string& name : unit.methods) {
      const MethodResults m = run_model_based(context, name, data, reconstruction, noisy);
      results.rows.insert(results.rows.end(), m.rows.begin(), m.rows.end());
    }
    for (const std::string& augment : unit.augments) {
      const LearnedResults l = run_learned(context, augment, learned, data, reconstruction, noisy);
      results.rows.insert(results.rows.end(), l.method.rows.begin(), l.method.rows.end());
      results.training.push_back(l.training);
    }
    if (!unit.sizes.empty()) {
      const auto points = run_sweep(context, learned, data, reconstruction, results, unit.sizes);
      results.efficiency.insert(results.efficiency.end(), points.begin(), points.end());
    }
    record.units.push_back({unit.name, seconds_since(t0)});
  }
  record.seconds = seconds_since(t_start);
  write_run_shard_record(out, record);
  return results;
}

}  // namespace
}  // namespace run

RunResults run_benchmark(const RunConfig& config) {
  using namespace run;
  if (config.shard_count > 1) return run_shard(config);
  const auto t_start = std::chrono::steady_clock::now();
  fix_threads(config);
  const fs::path out = output_folder(config);
  const FolderLock lock(out.string());  // one writer per output folder
  const std::string shards = config.merge_shards ? gather_shards(config) : "";
  const Context context = context_for(config, out);
  const double gemm_flops = gemm_peak(config);

  const RunData data = load_data(context);
  check_merge(config, data, shards);
  const Reconstruction reconstruction = set_up_reconstruction(context, data);
  const NoisyFrames noisy = noisy_copies(config, data);

  RunResults results;
  results.program = program_version();
  std::vector<ImageRow> figure;  // the first test frames: truth, then each method (noise-free)
  if (data.labelled)
    figure.push_back({"truth", first_images(data.test.labels, config.figure_samples)});
  for (const std::string& name : config.methods) {
    MethodResults m = run_model_based(context, name, data, reconstruction, noisy);
    results.rows.insert(results.rows.end(), m.rows.begin(), m.rows.end());
    figure.push_back({name, m.images});
  }
  LearnedSetup learned = learned_setup(config, data.source);
  learned.gemm_flops = gemm_flops;
  long long parameters = 0;
  const std::vector<std::string> augments = learned_augments(context, data);
  for (const std::string& augment : augments) {
    LearnedResults l = run_learned(context, augment, learned, data, reconstruction, noisy);
    results.rows.insert(results.rows.end(), l.method.rows.begin(), l.method.rows.end());
    results.training.push_back(l.training);
    figure.push_back({"dnn " + augment, l.method.images});
    parameters = l.parameters;
  }
  // The data-efficiency sweep compares none with d16 on the disk; a sensor of another shape has
  // its own group, whose sweep is not made yet.
  if (!has_sensor_mesh(data.sensor()))
    results.efficiency =
        run_sweep(context, learned, data, reconstruction, results, config.efficiency_sizes);
  if (!config.measured.empty())
    results.measured = run_measured(context, data, reconstruction, learned, augments, results);

  const double total_s = seconds_since(t_start);
  results.machine = describe_machine();
  results.configuration = describe_run(config, data, reconstruction, learned, parameters, total_s);
  results.configuration["fingerprint"] = run_fingerprint(config, data);
  results.recommendation = recommend(results.rows, results.training);
  write_run_store(out.string(), results, figure, reconstruction.grid);
  return draw_run_report(out.string());
}

}  // namespace eitbench
