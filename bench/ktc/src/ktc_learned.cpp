#include "eitbench/bench/ktc/ktc_learned.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "eitbench/bench/methods/metrics.h"
#include "eitbench/bench/methods/model_file.h"
#include "eitbench/bench/methods/training_run.h"
#include "eitbench/bench/support/timing.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/pixel_grid.h"

namespace eitbench {
namespace {

// Rows [begin, end) of a simulated set.
KtcSimulatedSet rows(const KtcSimulatedSet& s, int begin, int end) {
  KtcSimulatedSet out;
  out.frames = s.frames.middleRows(begin, end - begin);
  out.labels.assign(s.labels.begin() + begin, s.labels.begin() + end);
  out.targets.assign(s.targets.begin() + begin, s.targets.begin() + end);
  return out;
}

// The simulated test split's mean correlation (inside the tank) and mean KTC score; `t` is the
// split as the model reads it (frames or one-step images).
void score_test_split(const LearnedModel& model, const LabelledFrames& t,
                      const KtcSimulatedSet& test, const KtcSimulationOptions& simulation,
                      double radius, double threshold, KtcLearnedArm& arm) {
  const SampleMatrix out = model.reconstruct(t.frames);
  // CC over the tank's pixels, as every simulated benchmark scores it: the network's own mask.
  const PixelGrid grid(static_cast<int>(test.labels.at(0).rows()));
  const std::vector<bool> mask = model.image_mask();
  if (!std::equal(mask.begin(), mask.end(), grid.mask().begin(), grid.mask().end()))
    throw std::logic_error("score_test_split: the network's mask is not the tank's grid");
  KtcSimulationOptions full = simulation;
  full.grid = kKtcImageSize;
  double cc = 0, score = 0;
  for (Eigen::Index k = 0; k < out.rows(); ++k) {
    cc += correlation(out.row(k).transpose(), t.labels.row(k).transpose(), grid);
    const ClassImage truth = ktc_labels(test.targets[static_cast<std::size_t>(k)], radius, full);
    score += ktc_score(truth, ktc_output_classes(out.row(k).transpose(), threshold)).total();
  }
  arm.test_cc = cc / static_cast<double>(out.rows());
  arm.test_score = score / static_cast<double>(out.rows());
}

// Every sample at every level, as `eitbench ktc --method dnn` (or dnn-post) reconstructs them:
// `classes` of a change.
void score_samples(const std::function<ClassImage(const Eigen::VectorXd&)>& classes,
                   const KtcSetup& setup, const std::vector<KtcMeasurement>& samples,
                   const std::vector<ClassImage>& truths, const std::vector<int>& levels,
                   KtcLearnedArm& arm) {
  std::vector<double> ms;
  for (int level : levels) {
    arm.scores.emplace_back(), arm.classes.emplace_back();
    for (std::size_t s = 0; s < samples.size(); ++s) {
      const auto t0 = std::chrono::steady_clock::now();
      const ClassImage c = classes(ktc_difference(samples[s], setup, level));
      ms.push_back(1e3 * seconds_since(t0));
      arm.scores.back().push_back(ktc_score(truths[s], c).total());
      arm.classes.back().push_back(c);
    }
  }
  std::nth_element(ms.begin(), ms.begin() + static_cast<std::ptrdiff_t>(ms.size() / 2), ms.end());
  arm.median_ms = ms[ms.size() / 2];
}

// What the model file records beside the training: the tank, the contrasts, the level handling.
nlohmann::json ktc_record(const KtcSetup& setup, const KtcLearnedResults& r,
                          const std::string& network, const std::string& arm) {
  const KtcTank& t = setup.tank;
  nlohmann::json record = {
      {"network", network},
      {"arm", arm},
      {"threshold", r.options.network.threshold},
      {"levels",
       "one network for levels 1-7: each training frame at a level drawn from 1-7, "
       "a missing value given as 0"},
      {"group", arm == "group" ? "the tank's 8 elements (quarter turns and mirrors), on full "
                                 "frames before the level's values are removed"
                               : "none"},
      {"tank",
       {{"radius", t.options.radius},
        {"electrode_coverage", t.options.electrode_coverage},
        {"density", to_string(t.options.density)},
        {"background", t.background},
        {"contact_impedances",
         std::vector<double>(t.contact_impedances.data(),
                             t.contact_impedances.data() + t.contact_impedances.size())}}},
      {"contrasts",
       {{"resistive", {r.options.resistive_low, r.options.resistive_high}},
        {"conductive", {r.options.conductive_low, r.options.conductive_high}},
        {"drawn", "log-uniformly in each band, target by target"}}},
      {"noise", r.noise},
      {"simulated_tanks", r.train}};
  if (network == "dnn-post")
    record["one_step"] = {{"method", r.options.one_step.method},
                          {"lambda", r.options.one_step.lambda},
                          {"pixels", setup.grid.size()},
                          {"data_term", "the run's noise model (its settings)"}};
  return record;
}

// The simulated splits, and what every arm shares: the validation split as each network reads it,
// the one-step method (its level's factors built once).
struct Splits {
  KtcSimulatedSet train, validation, test;
  KtcSimulationOptions simulation;
  std::unique_ptr<MissingValues> one_step;  // with dnn-post only
  LabelledFrames validation_frames, validation_images;
};

struct ArmName {
  std::string network, arm;  // dnn | dnn-post, none | group
};

// Trains one network with or without the group into its model file and scores it.
KtcLearnedArm train_arm(const KtcSetup& setup, const std::vector<KtcMeasurement>& samples,
                        const std::vector<ClassImage>& truths, const std::vector<int>& levels,
                        const ArmName& name, const std::string& out, bool quiet, const Splits& sets,
                        const KtcLearnedResults& r) {
  const CurrentPatterns& patterns = setup.tank.protocol->patterns();
  const bool post = name.network == "dnn-post";
  KtcNetworkOptions n = r.options.network;
  n.group = name.arm == "group";
  const std::uint64_t seed = n.seed;
  const auto inputs = [&](const KtcSimulatedSet& s, bool group, std::uint64_t draw) {
    return post ? ktc_post_frames(s, patterns, group, draw, *sets.one_step, setup.grid)
                : ktc_network_frames(s, patterns, group, draw);
  };
  const LabelledFrames t = inputs(sets.train, n.group, seed);
  const int width = static_cast<int>(t.frames.cols());
  KtcLearnedArm a;
  a.network = name.network;
  a.arm = name.arm;
  a.model_file = ktc_model_path(out, name.network, name.arm);
  a.training_frames = t.frames.rows();
  TrainingRun run;
  run.out = a.model_file;
  run.quiet = quiet;
  run.label = name.network + " " + name.arm;
  run.rule = r.options.rule;
  const int grid = r.options.grid;
  TrainingResult trained = train_and_save(
      ktc_network_options(n, width, grid), ktc_training_options(n), t,
      post ? sets.validation_images : sets.validation_frames,
      post ? ktc_post_setup(patterns, grid, width) : ktc_network_setup(patterns, grid), run);
  auto training = nlohmann::json::parse(trained.model.info().training);
  training["ktc"] = ktc_record(setup, r, name.network, name.arm);
  trained.model.info().training = training.dump();
  trained.model.info().augment = n.group ? "ktc-group" : "none";
  write_model_file(a.model_file, trained.model);
  a.end = trained.end;
  a.steps = trained.total_steps;
  a.doublings = trained.doublings;
  a.stage_best = trained.stage_best;
  a.training_seconds = trained.seconds;
  const LearnedModel& model = trained.model;
  score_test_split(model, inputs(sets.test, false, seed + 2), sets.test, sets.simulation,
                   setup.tank.options.radius, n.threshold, a);
  const auto classes = [&](const Eigen::VectorXd& change) {
    return post ? ktc_post_classes(model, *sets.one_step, setup.grid, change, n.threshold)
                : ktc_network_classes(model, change, n.threshold);
  };
  score_samples(classes, setup, samples, truths, levels, a);
  return a;
}

}  // namespace

void KtcLearnedOptions::validate() const {
  for (std::size_t k = 0; k < networks.size(); ++k) {
    if (networks[k] != "dnn" && networks[k] != "dnn-post")
      throw InputError("--ktc-learned", "",
                       "'" + networks[k] + "': dnn (the frame) or dnn-post (a one-step image)");
    if (std::count(networks.begin(), networks.begin() + static_cast<std::ptrdiff_t>(k),
                   networks[k]))
      throw InputError("--ktc-learned", "", "lists " + networks[k] + " twice");
  }
  if (networks.empty() && !arms.empty())
    throw InputError("--ktc-learned", "", "names no network (--ktc-tanks 0: no learned rows)");
  one_step.validate();
  for (std::size_t k = 0; k < arms.size(); ++k) {
    if (arms[k] != "none" && arms[k] != "group")
      throw InputError("--augment", "",
                       "'" + arms[k] + "': a KTC run trains none and group (the tank's symmetry)");
    if (std::count(arms.begin(), arms.begin() + static_cast<std::ptrdiff_t>(k), arms[k]))
      throw InputError("--augment", "", "lists " + arms[k] + " twice");
  }
  if (!arms.empty() && tanks < 20)
    throw InputError("--ktc-tanks", "", "needs at least 20 simulated tanks (0: no learned rows)");
  if (training_bytes() > kKtcLearnedMemoryBudget)
    throw InputError(
        "--ktc-tanks", "",
        fmt::format("{} tanks would take about {:.1f} GiB to train on, more than the "
                    "{:.0f} GiB budget",
                    tanks, training_bytes() / (1 << 30), kKtcLearnedMemoryBudget / (1 << 30)));
  if (grid < 8 || grid > 256)
    throw InputError("KtcLearnedOptions", "grid", "must lie in 8 ... 256");
  // One spread serves both classes: the two bands span the same factor.
  if (!(resistive_low > 0 && resistive_low <= resistive_high && resistive_high < 1) ||
      !(conductive_low > 1 && conductive_low <= conductive_high &&
        std::isfinite(conductive_high)) ||
      std::abs(std::log(resistive_high / resistive_low) -
               std::log(conductive_high / conductive_low)) > 1e-9)
    throw InputError("KtcLearnedOptions", "resistive_low",
                     "the bands need 0 < low <= high < 1 (resistive), 1 < low <= high "
                     "(conductive), each spanning the same factor");
  network.validate();
  rule.validate();
  // The device this machine must have, before an hour of other work (InputError naming it).
  if (!arms.empty()) ktc_training_options(network).validate();
}

bool KtcLearnedOptions::trains(const std::string& network) const {
  return std::count(networks.begin(), networks.end(), network) > 0;
}

double KtcLearnedOptions::training_bytes() const {
  // Measured: 4,000 tanks with the group peaked at 4.8 GB (frames and labels as doubles, the
  // trainer's float copies, the simulated set): about 1.2 MB a tank, counted here as 1.5.
  const bool group = std::count(arms.begin(), arms.end(), "group") > 0;
  const bool post = trains("dnn-post");
  // A one-step image's pixels inside the tank (pi/4 of the square) beside the frame's values.
  const double image = post ? 0.8 * one_step_grid * one_step_grid : 0;
  const double values = 2356.0 + image + static_cast<double>(grid) * grid;
  return static_cast<double>(tanks) * (group ? 8 : 1) * values * 8 * 3.5;
}

std::string ktc_model_path(const std::string& run, const std::string& network,
                           const std::string& arm) {
  return (std::filesystem::path(run) / ("ktc_" + network + "_" + arm + ".model")).string();
}

namespace {

// The model's KTC record (ktc_record), or InputError(source, "ktc").
nlohmann::json ktc_model_record(const LearnedModel& model, const std::string& source) {
  const auto j = nlohmann::json::parse(model.info().training, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("ktc") || !j.at("ktc").is_object())
    throw InputError(source, "ktc", "is not a model a KTC run trained (eitbench run --ktc)");
  return j.at("ktc");
}

}  // namespace

double ktc_model_threshold(const LearnedModel& model, const std::string& source) {
  const nlohmann::json record = ktc_model_record(model, source);
  if (!record.contains("threshold") || !record.at("threshold").is_number())
    throw InputError(source, "ktc", "is not a model a KTC run trained (eitbench run --ktc)");
  const double t = record.at("threshold").get<double>();
  if (!(t > 0 && t < 1)) throw InputError(source, "ktc.threshold", "must lie in (0, 1)");
  return t;
}

KtcOneStep ktc_model_one_step(const LearnedModel& model, const std::string& source, int pixels) {
  const nlohmann::json ktc = ktc_model_record(model, source);
  const auto* record = ktc.contains("one_step") ? &ktc.at("one_step") : nullptr;
  if (!record || !record->is_object() || !record->contains("method") ||
      !record->contains("lambda") || !record->contains("pixels") ||
      !record->at("method").is_string() || !record->at("lambda").is_number() ||
      !record->at("pixels").is_number_integer())
    throw InputError(source, "ktc.one_step", "is not a post-processing model (dnn-post)");
  KtcOneStep step{record->at("method").get<std::string>(), record->at("lambda").get<double>()};
  step.validate();
  if (record->at("pixels").get<int>() != pixels)
    throw InputError(source, "ktc.one_step.pixels",
                     "reads one-step images of " + record->at("pixels").dump() +
                         " pixels a side, the run's grid has " + std::to_string(pixels));
  return step;
}

KtcSimulationOptions ktc_training_simulation(const KtcLearnedOptions& options,
                                             const KtcTank& tank) {
  KtcSimulationOptions so;
  so.samples = options.tanks;
  so.seed = static_cast<unsigned>(options.network.seed);
  // The band's geometric middle, spread to both ends.
  so.resistive = std::sqrt(options.resistive_low * options.resistive_high);
  so.conductive = std::sqrt(options.conductive_low * options.conductive_high);
  so.contrast_spread = std::sqrt(options.resistive_high / options.resistive_low);
  so.noise = repeated_pattern_noise(tank.reference, tank.protocol->patterns());
  return so;
}

KtcLearnedResults run_ktc_learned(const KtcSetup& setup, const std::vector<KtcMeasurement>& samples,
                                  const std::vector<ClassImage>& truths,
                                  const KtcContrastFits& contrasts, const std::vector<int>& levels,
                                  const KtcLearnedOptions& options, const std::string& out,
                                  bool quiet) {
  options.validate();
  KtcLearnedResults r;
  r.options = options;
  const CurrentPatterns& patterns = setup.tank.protocol->patterns();
  r.contrasts = contrasts;
  const KtcSimulationOptions so = ktc_training_simulation(options, setup.tank);
  r.noise = so.noise;
  r.in_band = r.contrasts.best_within(options.resistive_low, options.resistive_high,
                                      options.conductive_low, options.conductive_high);
  if (!quiet)
    fmt::print(stderr,
               "simulating {} tanks (contrasts {:.3g}-{:.3g} resistive, {:.3g}-{:.3g} "
               "conductive; noise {:.2g} V) ...\n",
               options.tanks, options.resistive_low, options.resistive_high, options.conductive_low,
               options.conductive_high, so.noise);
  const auto t0 = std::chrono::steady_clock::now();
  const KtcSimulatedSet all = simulate_ktc_tanks(setup.tank, so);
  r.simulation_seconds = seconds_since(t0);
  r.test = r.validation = std::max(1, options.tanks / 10);
  r.train = options.tanks - r.test - r.validation;
  Splits sets;
  sets.train = rows(all, 0, r.train);
  sets.validation = rows(all, r.train, r.train + r.validation);
  sets.test = rows(all, r.train + r.validation, options.tanks);
  sets.simulation = so;
  const std::uint64_t seed = options.network.seed;
  sets.validation_frames = ktc_network_frames(sets.validation, patterns, false, seed + 1);
  if (options.trains("dnn-post")) {
    if (!quiet)
      fmt::print(stderr, "one-step images ({} at lambda {:g}) of the simulated tanks ...\n",
                 options.one_step.method, options.one_step.lambda);
    sets.one_step = make_ktc_one_step(setup, options.one_step);
    sets.validation_images =
        ktc_post_frames(sets.validation, patterns, false, seed + 1, *sets.one_step, setup.grid);
  }
  for (const std::string& network : options.networks)
    for (const std::string& arm : options.arms)
      r.arms.push_back(
          train_arm(setup, samples, truths, levels, {network, arm}, out, quiet, sets, r));
  return r;
}

}  // namespace eitbench
