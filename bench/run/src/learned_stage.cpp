// Stage 4: the learned reconstructor, trained without and with augmentation, scored at each SNR.
#include <fmt/core.h>

#include <chrono>

#include <nlohmann/json.hpp>

#include "eitbench/bench/data/sensor.h"
#include "eitbench/bench/data/training_data.h"
#include "eitbench/bench/methods/model_file.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/bench/methods/training_run.h"
#include "eitbench/bench/support/timing.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/learned/schedule.h"
#include "stages.h"

namespace eitbench::run {
namespace fs = std::filesystem;
std::string learned_model_path(const Context& context, const std::string& augment) {
  return (context.out / "models" / ("dnn_" + augment + ".pt")).string();
}

TrainingSummary training_summary(const LearnedModel& model, const std::string& path,
                                 const LearnedSetup& setup) {
  TrainingSummary s;
  s.augment = model.info().augment;
  try {
    const nlohmann::json t = nlohmann::json::parse(model.info().training);
    s.history = history_from_json(t.at("history").dump(), path);
    s.best_round = t.at("best_round").get<int>();
    s.best_epoch = t.at("best_epoch").get<int>();
    s.converged = t.at("converged").get<bool>();
    // The budget rule's record (model files from before it: one stage, its end by the flag).
    s.end = t.value("end", std::string(s.converged ? "early stopping" : "budget"));
    s.doublings = t.value("doublings", 0);
    s.budget_steps = t.value("budget_steps", 0LL);
    s.stage_best = t.value("stage_best", std::vector<double>());
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, "training", std::string("not this eitbench's record: ") + e.what());
  }
  for (const auto& e : s.history) s.seconds += e.seconds;
  if (!s.history.empty()) s.steps = s.history.back().steps, s.samples = s.history.back().samples;
  s.samples_per_second = s.seconds > 0 ? double(s.samples) / s.seconds : 0;
  if (setup.gemm_flops > 0)
    s.fraction_of_gemm_peak =
        3 * forward_flops(model.info().network) * s.samples_per_second / setup.gemm_flops;
  return s;
}

namespace {

// The model in <out>/models/dnn_<augment>.pt: read back when resuming a run that trained it for
// the same data and options (`read_back`), trained otherwise (from its checkpoint when one is
// left).
LearnedModel trained_model(const Context& context, const std::string& augment,
                           const LearnedSetup& setup, const RunData& data, bool& read_back) {
  const RunConfig& config = context.config;
  const Dataset& source = data.source;
  const std::string path = learned_model_path(context, augment);
  Provenance provenance = training_provenance(config, data);
  provenance["augment"] = augment;
  const bool claimed =
      context.cache.claim_model("dnn " + augment, path, provenance,
                                kept_under_earlier_edge(config, provenance, path, setup.training));
  read_back = claimed && fs::exists(path);
  if (read_back) {
    context.say(fmt::format("dnn {}: resumed from {}", augment, path));
    return read_model_file(path);
  }
  TrainingOptions o = setup.training;
  o.augment = parse_group(augment, "augment");
  o.epochs = config.epochs;
  TrainingRun run;
  run.out = path;
  run.resume = claimed && resumable(path);
  run.quiet = config.quiet;
  run.label = "dnn " + augment;
  run.curves = false;
  run.rule = config.budget_rule;
  context.say(fmt::format(
      "dnn {}: training the {} model on {} samples until validation stops improving ({} epochs, "
      "then up to {} doublings)",
      augment, config.model, source.indices(Split::train).size(), config.epochs,
      config.budget_rule.max_doublings));
  TrainingResult r =
      train_and_save(setup.network, o, labelled_frames(source, Split::train),
                     labelled_frames(source, Split::validation), sensor_of(source), run);
  return std::move(r.model);
}

// The budget rule in a provenance. `edge` names where a stop has rate left (budget_rule.h):
// kRateLeftEdge now, kEarlierRateLeftEdge for models trained before it moved.
std::string budget_rule_text(const BudgetRule& rule, const char* edge) {
  return fmt::format("{} doublings, tolerance {:g}, rate left at {}, doublings to the floor",
                     rule.max_doublings, rule.tolerance, edge);
}
constexpr const char* kRateLeftEdge = "a tenth of the cosine's range";
constexpr const char* kEarlierRateLeftEdge = "2x the floor";

}  // namespace

StageCache::Keep kept_under_earlier_edge(const RunConfig& config, const Provenance& wanted,
                                         const std::string& model_path,
                                         const TrainingOptions& options) {
  return [budget = config.budget_rule, wanted, model_path, options](const Provenance& stored) {
    Provenance now = stored;
    const auto rule = now.find("budget rule");
    if (rule == now.end() || rule->second != budget_rule_text(budget, kEarlierRateLeftEdge))
      return false;
    rule->second = budget_rule_text(budget, kRateLeftEdge);
    if (now != wanted || !fs::exists(model_path)) return false;
    // The model file must be the one that record describes: a model trained again since (a sweep
    // point killed between its training and its score) has the present rule in its own record,
    // and the earlier point's figures are not its.
    const Provenance own = model_provenance(model_path);
    const auto own_rule = own.find("budget rule");
    if (own_rule == own.end() || own_rule->second != budget_rule_text(budget, kEarlierRateLeftEdge))
      return false;
    try {
      return decided_as_now(read_model_file(model_path), options);
    } catch (const std::exception&) {
      return false;  // unreadable: trained again
    }
  };
}

Provenance training_provenance(const RunConfig& config, const RunData& data) {
  Provenance p{{"program", data.provenance.at("program")},
               {"training data", data.own_training ? data.provenance.at("data")
                                                   : data.provenance.at("training data")},
               {"model", config.model},
               {"epochs", std::to_string(config.epochs)},
               {"batch", std::to_string(config.batch)},
               {"learning rate", fmt::format("{:g}", config.learning_rate)},
               {"schedule", config.schedule},
               {"validate every", std::to_string(config.validate_every)},
               {"patience", std::to_string(config.patience)},
               {"min improvement", fmt::format("{:g}", config.min_improvement)},
               // A stop counts as early stopping only before the cosine's last fifth
               // (budget_rule.h), and a doubling runs its cosine to the floor before it may stop:
               // models stored under an older rule are trained again rather than resumed with its
               // decisions, unless they made the same (kept_under_earlier_edge).
               {"budget rule", budget_rule_text(config.budget_rule, kRateLeftEdge)},
               {"seed", std::to_string(config.seed)},
               {"device", resolve_device(config.device, "--device")}};
  // Only where it is not the schedule's default: a run made before --decay resumes as it was.
  if (config.decay != ScheduleOptions().decay_fraction)
    p["decay"] = fmt::format("{:g}", config.decay);
  return p;
}

LearnedSetup learned_setup(const RunConfig& config, const Dataset& source) {
  LearnedSetup s;
  const ModelSize size = parse_model_size(config.model, "model");
  s.network =
      NetworkOptions::preset(size, static_cast<int>(source.differences.cols()), source.image_size);
  s.network.radius = source.radius;
  s.network.mask = sensor_mask(source);  // a sensor of another shape masks to its own
  s.training.batch_size = config.batch;
  s.training.learning_rate = config.learning_rate;
  s.training.schedule.kind = parse_schedule(config.schedule, "schedule");
  s.training.schedule.decay_fraction = config.decay;
  s.training.validate_every = config.validate_every;
  s.training.patience = config.patience;
  s.training.min_improvement = config.min_improvement;
  s.training.seed = config.seed;
  s.training.device = resolve_device(config.device, "--device");
  return s;
}

namespace {

// One frame at a time (median of 200) and batches of 1,000 frames on the GPU the model trained
// on, host memory in and out, after a warm-up of each: the figures a GPU deployment would see.
void time_device_inference(const LearnedModel& trained, const SampleMatrix& frames,
                           const std::string& device, TrainingSummary& summary) {
  if (device == "cpu" || frames.rows() == 0) return;
  LearnedModel model = trained;
  model.to_device(device);
  using clock = std::chrono::steady_clock;
  std::vector<double> one;
  for (int k = 0; k < 220; ++k) {
    const Eigen::VectorXd frame = frames.row(k % frames.rows()).transpose();
    const auto t0 = clock::now();
    (void)model.reconstruct(frame);
    if (k >= 20)
      one.push_back(std::chrono::duration<double, std::milli>(clock::now() - t0).count());
  }
  const Eigen::Index n = std::min<Eigen::Index>(1000, frames.rows());
  const SampleMatrix batch = frames.topRows(n);
  (void)model.reconstruct(batch, 1000);
  const int repeats = 10;
  const auto t0 = clock::now();
  for (int k = 0; k < repeats; ++k) (void)model.reconstruct(batch, 1000);
  const double seconds = seconds_since(t0);
  summary.inference_device = model.device();
  summary.device_latency_ms = percentile(one, 0.5);
  summary.device_frames_per_second = repeats * double(n) / seconds;
}

// Trains (or reads back) the model and scores it at every SNR.
LearnedResults train_and_score(const Context& context, const std::string& augment,
                               const LearnedSetup& setup, const RunData& data,
                               const Reconstruction& reconstruction, const NoisyFrames& noisy,
                               bool& read_back) {
  const RunConfig& config = context.config;
  LearnedResults out;
  LearnedModel model = trained_model(context, augment, setup, data, read_back);
  out.training = training_summary(model, learned_model_path(context, augment), setup);
  out.training.augment = augment;  // the run's name: "group" on a sensor of another shape
  const TrainingSummary& summary = out.training;
  if (model.info().electrodes != data.data.electrodes)
    throw InputError(learned_model_path(context, augment), "electrodes",
                     "the model does not fit the data's sensor");
  out.parameters = model.parameters();
  const std::string device = resolve_device(config.device, "--device");
  time_device_inference(model, data.test.frames, device, out.training);
  if (!out.training.inference_device.empty())
    context.say(
        fmt::format("dnn {:>9} on {}: {:.3f} ms a frame, {:.0f} frames/s in batches of "
                    "1,000",
                    augment, out.training.inference_device, out.training.device_latency_ms,
                    out.training.device_frames_per_second));
  // Scored and timed where it trained: on a GPU run its per-frame figures are the GPU's (the
  // report says so), not the CPU's beside the model-based methods' many threads.
  if (device != "cpu") model.to_device(device);
  const auto method = make_learned_reconstructor(model);
  for (std::size_t k = 0; k < data.snrs.size(); ++k) {
    SampleMatrix images;
    ResultRow row =
        evaluate_row(*method, noisy.test[k], data.labelled ? data.test.labels : SampleMatrix(),
                     reconstruction.grid, config.timed_frames, &images);
    row.method = "dnn", row.augment = augment, row.snr_db = data.snrs[k];
    row.setup_s = summary.seconds;
    row.touch = touch_scores(context, data, reconstruction, *method, noisy.validation[k], images);
    context.say(fmt::format("dnn {:>9} at {:>3} dB: {}, {:.3g} ms a frame", augment,
                            snr_label(data.snrs[k]), quality(row), row.latency_median_ms));
    if (k == 0) out.method.images = first_images(images, config.figure_samples);
    out.method.rows.push_back(row);
  }
  return out;
}

nlohmann::json to_json(const LearnedResults& r) {
  return {{"method", to_json(r.method)},
          {"training", to_json(r.training)},
          {"parameters", r.parameters}};
}

LearnedResults learned_results_from(const nlohmann::json& j, const std::string& source) {
  LearnedResults r;
  r.method = method_results_from(j.at("method"));
  r.training = training_summary_from_json(j.at("training"), source);
  r.parameters = j.at("parameters").get<long long>();
  return r;
}

}  // namespace

// A learned model's scores are recorded as a stage too, beside its model file. While the model
// is there, a resumed run reads it and scores it again (a merge times it again, alone), and a
// record that matches it is left as it is (a finished shard stays file for file). A run whose
// models are gone, moved to another machine with its stages/ folder only (a GPU session's files
// back are a few MB; a paper model is 19 MB), resumes from the record, unless it reconstructs
// real presses (--measured), which needs the models themselves: those are trained again.
LearnedResults run_learned(const Context& context, const std::string& augment,
                           const LearnedSetup& setup, const RunData& data,
                           const Reconstruction& reconstruction, const NoisyFrames& noisy) {
  const std::string stage = "dnn_" + augment, model = learned_model_path(context, augment);
  Provenance provenance = data.provenance;
  for (const auto& [key, value] : training_provenance(context.config, data))
    provenance[key] = value;
  provenance["augment"] = augment;
  LearnedResults out;
  const bool recorded = context.cache.find(
      stage, provenance, [&](const nlohmann::json& j) { out = learned_results_from(j, stage); });
  if (recorded && !fs::exists(model) && context.config.measured.empty()) {
    context.say(
        fmt::format("dnn {}: resumed from its record (the model file is not here)", augment));
    return out;
  }
  bool read_back = false;
  out = train_and_score(context, augment, setup, data, reconstruction, noisy, read_back);
  if (!recorded || !read_back) context.cache.save(stage, provenance, to_json(out));
  return out;
}

}  // namespace eitbench::run
