// Stage 4: the learned reconstructor, trained without and with augmentation, scored at each SNR.
#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include "eitbench/bench/data/training_data.h"
#include "eitbench/bench/methods/model_file.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/bench/methods/training_run.h"
#include "eitbench/jacobian/error.h"
#include "stages.h"

namespace eitbench::run {
namespace fs = std::filesystem;
namespace {

std::string model_path(const Context& context, const std::string& augment) {
  return (context.out / "models" / ("dnn_" + augment + ".pt")).string();
}

// The model in <out>/models/dnn_<augment>.pt: read back when resuming, trained otherwise (from its
// checkpoint when one is left). The summary's history and best epoch are filled in.
LearnedModel trained_model(const Context& context, const std::string& augment,
                           const LearnedSetup& setup, const Dataset& source,
                           TrainingSummary& summary) {
  const RunConfig& config = context.config;
  const std::string path = model_path(context, augment);
  if (config.resume && fs::exists(path)) {
    LearnedModel model = read_model_file(path);
    const nlohmann::json t = nlohmann::json::parse(model.info().training);
    summary.history = history_from_json(t.at("history").dump(), path);
    summary.best_epoch = t.at("best_epoch").get<int>();
    context.say(fmt::format("dnn {}: resumed from {}", augment, path));
    return model;
  }
  TrainingOptions o = setup.training;
  o.augment = parse_group(augment, "augment");
  o.epochs = config.epochs;
  TrainingRun run;
  run.out = path;
  run.resume = config.resume && fs::exists(checkpoint_path(path));
  run.quiet = config.quiet;
  run.label = "dnn " + augment;
  run.curves = false;
  context.say(fmt::format("dnn {}: training the {} model, {} epochs of {} samples", augment,
                          config.model, config.epochs, source.indices(Split::train).size()));
  TrainingResult r =
      train_and_save(setup.network, o, labelled_frames(source, Split::train),
                     labelled_frames(source, Split::validation), sensor_of(source), run);
  summary.history = r.history;
  summary.best_epoch = r.best_epoch;
  return std::move(r.model);
}

}  // namespace

LearnedSetup learned_setup(const RunConfig& config, const Dataset& source) {
  LearnedSetup s;
  const ModelSize size = parse_model_size(config.model, "model");
  s.network =
      NetworkOptions::preset(size, static_cast<int>(source.differences.cols()), source.image_size);
  s.network.radius = source.radius;
  s.training.batch_size = config.batch;
  s.training.learning_rate = config.learning_rate;
  s.training.seed = config.seed;
  s.training.device = resolve_device(config.device, "--device");
  return s;
}

LearnedResults run_learned(const Context& context, const std::string& augment,
                           const LearnedSetup& setup, const RunData& data,
                           const Reconstruction& reconstruction, const NoisyFrames& noisy) {
  const RunConfig& config = context.config;
  LearnedResults out;
  TrainingSummary& summary = out.training;
  summary.augment = augment;
  const LearnedModel model = trained_model(context, augment, setup, data.source, summary);
  for (const auto& e : summary.history)
    summary.seconds += e.seconds, summary.samples += e.samples_per_second * e.seconds;
  summary.samples_per_second = summary.seconds > 0 ? summary.samples / summary.seconds : 0;
  if (!summary.history.empty()) summary.steps = summary.history.back().steps;
  if (model.info().electrodes != data.data.electrodes)
    throw InputError(model_path(context, augment), "electrodes",
                     "the model does not fit the data's sensor");
  out.parameters = model.parameters();
  const auto method = make_learned_reconstructor(model);
  for (std::size_t k = 0; k < data.snrs.size(); ++k) {
    SampleMatrix images;
    ResultRow row =
        evaluate_row(*method, noisy.test[k], data.labelled ? data.test.labels : SampleMatrix(),
                     reconstruction.grid, config.timed_frames, &images);
    row.method = "dnn", row.augment = augment, row.snr_db = data.snrs[k];
    row.setup_s = summary.seconds;
    context.say(fmt::format("dnn {:>9} at {:>3} dB: {}, {:.3g} ms a frame", augment,
                            snr_label(data.snrs[k]), quality(row), row.latency_median_ms));
    if (k == 0) out.method.images = first_images(images, config.figure_samples);
    out.method.rows.push_back(row);
  }
  return out;
}

}  // namespace eitbench::run
