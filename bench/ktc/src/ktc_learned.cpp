#include "eitbench/bench/ktc/ktc_learned.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "eitbench/bench/methods/model_file.h"
#include "eitbench/bench/methods/training_run.h"
#include "eitbench/bench/support/timing.h"
#include "eitbench/jacobian/error.h"

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

double correlation(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const Eigen::VectorXd x = a.array() - a.mean(), y = b.array() - b.mean();
  const double d = x.norm() * y.norm();
  return d > 0 ? x.dot(y) / d : 0.0;
}

// The simulated test split's mean correlation (inside the tank) and mean KTC score.
void score_test_split(const LearnedModel& model, const KtcSimulatedSet& test,
                      const CurrentPatterns& patterns, const KtcSimulationOptions& simulation,
                      double radius, double threshold, std::uint64_t seed, KtcLearnedArm& arm) {
  const LabelledFrames t = ktc_network_frames(test, patterns, false, seed);
  const SampleMatrix out = model.reconstruct(t.frames);
  const std::vector<bool> mask = model.image_mask();
  KtcSimulationOptions full = simulation;
  full.grid = kKtcImageSize;
  double cc = 0, score = 0;
  for (Eigen::Index k = 0; k < out.rows(); ++k) {
    std::vector<double> a, b;
    for (std::size_t p = 0; p < mask.size(); ++p)
      if (mask[p]) a.push_back(out(k, static_cast<Eigen::Index>(p))), b.push_back(t.labels(k, p));
    cc += correlation(Eigen::Map<Eigen::VectorXd>(a.data(), static_cast<Eigen::Index>(a.size())),
                      Eigen::Map<Eigen::VectorXd>(b.data(), static_cast<Eigen::Index>(b.size())));
    Eigen::VectorXd frame = t.frames.row(k).transpose();
    const ClassImage truth = ktc_labels(test.targets[static_cast<std::size_t>(k)], radius, full);
    score += ktc_score(truth, ktc_network_classes(model, frame, threshold)).total();
  }
  arm.test_cc = cc / static_cast<double>(out.rows());
  arm.test_score = score / static_cast<double>(out.rows());
}

// Every sample at every level, as `eitbench ktc --method dnn` reconstructs them.
void score_samples(const LearnedModel& model, const KtcSetup& setup,
                   const std::vector<KtcMeasurement>& samples,
                   const std::vector<ClassImage>& truths, const std::vector<int>& levels,
                   double threshold, KtcLearnedArm& arm) {
  std::vector<double> ms;
  for (int level : levels) {
    arm.scores.emplace_back(), arm.classes.emplace_back();
    for (std::size_t s = 0; s < samples.size(); ++s) {
      const auto t0 = std::chrono::steady_clock::now();
      const ClassImage c =
          ktc_network_classes(model, ktc_difference(samples[s], setup, level), threshold);
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
                          const std::string& arm) {
  const KtcTank& t = setup.tank;
  return {{"arm", arm},
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
}

}  // namespace

void KtcLearnedOptions::validate() const {
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

double KtcLearnedOptions::training_bytes() const {
  // Measured: 4,000 tanks with the group peaked at 4.8 GB (frames and labels as doubles, the
  // trainer's float copies, the simulated set): about 1.2 MB a tank, counted here as 1.5.
  const bool group = std::count(arms.begin(), arms.end(), "group") > 0;
  const double values = 2356.0 + static_cast<double>(grid) * grid;
  return static_cast<double>(tanks) * (group ? 8 : 1) * values * 8 * 3.5;
}

std::string ktc_model_path(const std::string& run, const std::string& arm) {
  return (std::filesystem::path(run) / ("ktc_dnn_" + arm + ".model")).string();
}

double ktc_model_threshold(const LearnedModel& model, const std::string& source) {
  const auto j = nlohmann::json::parse(model.info().training, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("ktc") || !j.at("ktc").is_object() ||
      !j.at("ktc").contains("threshold") || !j.at("ktc").at("threshold").is_number())
    throw InputError(source, "ktc", "is not a model a KTC run trained (eitbench run --ktc)");
  const double t = j.at("ktc").at("threshold").get<double>();
  if (!(t > 0 && t < 1)) throw InputError(source, "ktc.threshold", "must lie in (0, 1)");
  return t;
}

KtcLearnedResults run_ktc_learned(const KtcSetup& setup, const std::vector<KtcMeasurement>& samples,
                                  const std::vector<ClassImage>& truths,
                                  const std::vector<int>& levels, const KtcLearnedOptions& options,
                                  const std::string& out, bool quiet) {
  options.validate();
  KtcLearnedResults r;
  r.options = options;
  const CurrentPatterns& patterns = setup.tank.protocol->patterns();
  std::vector<Eigen::VectorXd> changes;
  for (const KtcMeasurement& m : samples) changes.push_back(ktc_difference(m, setup, 1));
  r.contrasts = fit_ktc_contrasts_held_out(setup.tank, changes, truths, setup.orientation);
  r.noise = repeated_pattern_noise(setup.tank.reference, patterns);
  KtcSimulationOptions so;
  so.samples = options.tanks;
  so.seed = static_cast<unsigned>(options.network.seed);
  // The band's geometric middle, spread to both ends.
  so.resistive = std::sqrt(options.resistive_low * options.resistive_high);
  so.conductive = std::sqrt(options.conductive_low * options.conductive_high);
  so.contrast_spread = std::sqrt(options.resistive_high / options.resistive_low);
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
  const KtcSimulatedSet train = rows(all, 0, r.train),
                        validation = rows(all, r.train, r.train + r.validation),
                        test = rows(all, r.train + r.validation, options.tanks);
  const std::uint64_t seed = options.network.seed;
  const LabelledFrames v = ktc_network_frames(validation, patterns, false, seed + 1);
  for (const std::string& arm : options.arms) {
    KtcNetworkOptions n = options.network;
    n.group = arm == "group";
    const LabelledFrames t = ktc_network_frames(train, patterns, n.group, seed);
    KtcLearnedArm a;
    a.arm = arm;
    a.model_file = ktc_model_path(out, arm);
    a.training_frames = t.frames.rows();
    TrainingRun run;
    run.out = a.model_file;
    run.quiet = quiet;
    run.label = "dnn " + arm;
    run.rule = options.rule;
    TrainingResult trained = train_and_save(
        ktc_network_options(n, static_cast<int>(t.frames.cols()), options.grid),
        ktc_training_options(n), t, v, ktc_network_setup(patterns, options.grid), run);
    auto training = nlohmann::json::parse(trained.model.info().training);
    training["ktc"] = ktc_record(setup, r, arm);
    trained.model.info().training = training.dump();
    trained.model.info().augment = arm == "group" ? "ktc-group" : "none";
    write_model_file(a.model_file, trained.model);
    a.end = trained.end;
    a.steps = trained.total_steps;
    a.doublings = trained.doublings;
    a.stage_best = trained.stage_best;
    a.training_seconds = trained.seconds;
    score_test_split(trained.model, test, patterns, so, setup.tank.options.radius, n.threshold,
                     seed + 2, a);
    score_samples(trained.model, setup, samples, truths, levels, n.threshold, a);
    r.arms.push_back(std::move(a));
  }
  return r;
}

}  // namespace eitbench
