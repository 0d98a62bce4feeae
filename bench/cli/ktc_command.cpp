// eitbench ktc: KTC2023's calling convention. Reads every dataN.mat and ref.mat of a folder and
// writes N.mat holding `reconstruction` (256 x 256 uint8: 0 water, 1 resistive, 2 conductive) for
// each, as a submission to the challenge did; scores each against trueN.mat where the folder has
// one.
#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>

#include "commands.h"
#include "eitbench/bench/io/content_hash.h"
#include "eitbench/bench/ktc/ktc_learned.h"
#include "eitbench/bench/ktc/ktc_method.h"
#include "eitbench/bench/ktc/ktc_report.h"
#include "eitbench/bench/methods/model_file.h"
#include "eitbench/bench/support/timing.h"
#include "eitbench/jacobian/error.h"

namespace eitbench::cli {
namespace {

struct KtcCommandArgs {
  std::string input, output, method = "noser", from, segmentation, density = "medium",
                             augment = "group", setting = "samples";
  int level = 1, pixels = 64;
  double lambda = 0, resistive = 0, conductive = 0, coverage = KtcTankOptions().electrode_coverage;
  KtcNoise noise;
  bool quiet = false;
};

// OUTPUT may not be INPUT (nor a file): KTC's folders hold the inputs.
void check_folders(const KtcCommandArgs& a) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(a.output, ec) && !fs::is_directory(a.output, ec))
    throw InputError(a.output, "", "OUTPUT_FOLDER is a file, not a folder");
  if (fs::exists(a.output, ec) && fs::equivalent(a.input, a.output, ec))
    throw InputError(a.output, "",
                     "OUTPUT_FOLDER is INPUT_FOLDER: the reconstructions would go among the "
                     "measurements; choose another folder");
}

// The run's tank where it calibrated this very ref.mat, else a fresh calibration.
KtcTank tank_for(const KtcMeasurement& reference, const std::string& ref_path,
                 const std::optional<KtcRunSettings>& run, const KtcTankOptions& options,
                 bool quiet) {
  if (run && run->reference_hash == file_hash(ref_path)) {
    if (!quiet) fmt::print(stderr, "the tank as {} calibrated it\n", run->path);
    return ktc_tank_at(reference, run->tank, run->background, run->contact_impedances);
  }
  if (!quiet)
    fmt::print(stderr, "calibrating the tank to {}{} ...\n", ref_path,
               run ? " (not the reference the run calibrated to)" : "");
  return calibrate_ktc_tank(reference, run ? run->tank : options);
}

// Every input read and checked before anything is written.
struct Inputs {
  KtcFolder folder;
  KtcMeasurement reference;
  std::vector<KtcMeasurement> data;
  std::vector<std::optional<ClassImage>> truths;
};

Inputs read_inputs(const KtcCommandArgs& a) {
  Inputs in;
  in.folder = scan_ktc_folder(a.input);
  in.reference = read_ktc_measurement(in.folder.reference);
  for (const auto& s : in.folder.samples) {
    in.data.push_back(read_ktc_measurement(s.data));
    check_same_patterns(in.data.back(), in.reference.patterns);
    in.truths.push_back(s.truth.empty() ? std::nullopt : std::optional(read_ktc_truth(s.truth)));
    const Eigen::VectorXd level =
        ktc_level_frame(in.data.back().voltages, in.reference.patterns, a.level);
    if (!level.array().isFinite().any())
      throw InputError(s.data, "Uel", "has no value level " + std::to_string(a.level) + " keeps");
  }
  return in;
}

// Writes OUTPUT/N.mat for every sample (classes(k) its segmentation), timed, scored where the
// folder has the truth; then the summary line `what`.
void write_all(const KtcCommandArgs& a, const Inputs& in,
               const std::function<ClassImage(std::size_t)>& classes, const std::string& what) {
  std::error_code error;
  std::filesystem::create_directories(a.output, error);
  if (error) throw InputError(a.output, "", "cannot create the folder: " + error.message());
  double total = 0;
  int scored = 0;
  for (std::size_t k = 0; k < in.data.size(); ++k) {
    const int number = in.folder.samples[k].number;
    const auto start = std::chrono::steady_clock::now();
    const ClassImage c = classes(k);
    const double ms = 1e3 * seconds_since(start);
    const std::string path =
        (std::filesystem::path(a.output) / (std::to_string(number) + ".mat")).string();
    write_ktc_reconstruction(path, c);
    std::string line = fmt::format("{}: {} ({:.1f} ms)", number, path, ms);
    if (in.truths[k]) {
      const double score = ktc_score(*in.truths[k], c).total();
      total += score, ++scored;
      line += fmt::format(", score {:.6f}", score);
    }
    if (!a.quiet) fmt::print("{}\n", line);
  }
  if (!a.quiet) {
    fmt::print("{}\n", what);
    if (scored > 0)
      fmt::print("score {:.3f} over {} samples (mean {:.3f}; the challenge sums 3 a level)\n",
                 total, scored, total / scored);
  }
}

// --method dnn or dnn-post: a learned model of the run, on the differences from ref.mat.
void run_learned(const KtcCommandArgs& a, const CLI::App& cmd) {
  if (a.from.empty())
    throw InputError(
        "--method", "",
        a.method + " is a model a KTC run trained: add --from RUN (eitbench run --ktc)");
  for (const char* flag :
       {"--lambda", "--segmentation", "--resistive", "--conductive", "--noise-relative",
        "--noise-floor", "--pixels", "--electrode-coverage", "--density"})
    if (cmd.count(flag) > 0)
      throw InputError(flag, "",
                       "does not apply to --method " + a.method +
                           " (the run's model segments itself, on the run's tank and grid)");
  if (a.augment != "none" && a.augment != "group")
    throw InputError("--augment", "", "'" + a.augment + "': none or group");
  check_folders(a);
  const KtcRunSettings settings = read_ktc_settings(a.from);
  const auto it = settings.models.find(a.method + " " + a.augment);
  if (it == settings.models.end())
    throw InputError("--from", "",
                     settings.path + " trained no " + a.method + " " + a.augment + " model");
  const LearnedModel model = read_model_file(it->second);
  const double threshold = ktc_model_threshold(model, it->second);
  const Inputs in = read_inputs(a);
  const MeasurementProtocol protocol = model.protocol();
  if (!protocol.has_patterns() || !(protocol.patterns() == in.reference.patterns))
    throw InputError(it->second, "protocol",
                     "was trained on other current patterns than " + in.folder.reference + "'s");
  std::vector<Eigen::VectorXd> changes;
  for (const auto& d : in.data)
    changes.push_back(
        ktc_level_frame(d.voltages - in.reference.voltages, in.reference.patterns, a.level));
  const std::string what = fmt::format("{} {} at level {}: {}, threshold {:.2g}", a.method,
                                       a.augment, a.level, it->second, threshold);
  if (a.method == "dnn")
    return write_all(
        a, in, [&](std::size_t k) { return ktc_network_classes(model, changes[k], threshold); },
        what);
  // dnn-post: the one-step image on the run's tank, grid and data term, as the run made it.
  const KtcOneStep step = ktc_model_one_step(model, it->second, settings.grid);
  const KtcSetup setup = make_ktc_setup(
      tank_for(in.reference, in.folder.reference, settings, KtcTankOptions(), a.quiet),
      settings.grid, settings.noise);
  const std::unique_ptr<MissingValues> one_step = make_ktc_one_step(setup, step);
  write_all(
      a, in,
      [&](std::size_t k) {
        return ktc_post_classes(model, *one_step, setup.grid, changes[k], threshold);
      },
      what + fmt::format(", on {} at lambda {:g}", step.method, step.lambda));
}

// The run's setting of a.method that --setting names: tuned on the samples, on the run's
// simulated tanks, or on both. InputError naming --setting or --from where the run has none.
const KtcRunSettings::Method& run_setting(const KtcCommandArgs& a, const KtcRunSettings& run) {
  const bool samples = a.setting == "samples";
  const auto& tuned = samples                     ? run.methods
                      : a.setting == "simulation" ? run.simulation_tuned
                                                  : run.joint_tuned;
  const auto it = tuned.find(a.method);
  if (it != tuned.end()) return it->second;
  if (!samples)
    throw InputError("--setting", "",
                     run.path + " has no setting of " + a.method + " tuned on " +
                         (a.setting == "simulation" ? "simulated tanks" : "samples and tanks") +
                         " (its run's --tuning-tanks and --tune-on-simulation)");
  throw InputError("--from", "", run.path + " has no setting of " + a.method);
}

void run(const KtcCommandArgs& a, const CLI::App& cmd) {
  ktc_removed_electrodes(a.level);  // 1 ... 7, before anything is read
  if (a.setting != "samples" && a.setting != "simulation" && a.setting != "joint")
    throw InputError("--setting", "",
                     "'" + a.setting + "' is none of samples, simulation and joint");
  if (a.setting != "samples" && a.from.empty())
    throw InputError("--setting", "", "takes a run's setting: add --from RUN");
  if ((a.method == "dnn" || a.method == "dnn-post") && cmd.count("--setting") > 0)
    throw InputError("--setting", "",
                     "picks a model-based method's setting, not a learned model's");
  if (a.method == "dnn" || a.method == "dnn-post") return run_learned(a, cmd);
  if (cmd.count("--augment") > 0)
    throw InputError("--augment", "",
                     "goes with --method dnn or dnn-post (the run's learned models)");
  ktc_candidates(a.method);  // a method KTC's frames can be reconstructed by
  check_folders(a);
  std::optional<KtcRunSettings> settings;
  if (!a.from.empty()) settings = read_ktc_settings(a.from);
  KtcTankOptions tank_options;
  tank_options.electrode_coverage = a.coverage;
  tank_options.density = parse_density(a.density);
  KtcNoise noise = a.noise;
  int pixels = a.pixels;
  const KtcSetting preset = ktc_default_setting(a.method);
  if (cmd.count("--noise-relative") == 0) noise.relative = preset.noise_relative;
  double lambda = a.lambda > 0 ? a.lambda : preset.lambda;
  SegmentationRule rule = preset.rule;
  if (settings) {
    const KtcRunSettings::Method& tuned = run_setting(a, *settings);
    if (cmd.count("--noise-relative") + cmd.count("--noise-floor") + cmd.count("--pixels") +
            cmd.count("--electrode-coverage") + cmd.count("--density") >
        0)
      throw InputError("--from", "",
                       "sets the tank, the noise and the grid as the run had them: leave out "
                       "--electrode-coverage, --density, --noise-*, --pixels");
    noise = settings->noise;
    noise.relative = tuned.noise_relative;
    pixels = settings->grid;
    if (a.lambda == 0) lambda = tuned.lambda;
    rule = tuned.rule;
  }
  if (!a.segmentation.empty()) rule.kind = parse_segmentation(a.segmentation);
  if ((a.resistive > 0 || a.conductive > 0) && rule.kind != SegmentationKind::levels)
    throw InputError(a.resistive > 0 ? "--resistive" : "--conductive", "",
                     "sets the levels rule: add --segmentation levels");
  if (a.resistive > 0) rule.resistive = a.resistive;
  if (a.conductive > 0) rule.conductive = a.conductive;
  rule.validate();
  noise.validate();
  check_ktc_grid(pixels);
  const Inputs in = read_inputs(a);
  const auto t0 = std::chrono::steady_clock::now();
  const KtcSetup setup = make_ktc_setup(
      tank_for(in.reference, in.folder.reference, settings, tank_options, a.quiet), pixels, noise);
  const std::unique_ptr<MissingValues> method = make_ktc_method(setup, a.method, lambda);
  std::vector<Eigen::VectorXd> frames;
  for (const auto& d : in.data) frames.push_back(ktc_difference(d, setup, a.level));
  for (const auto& f : frames) method->method_for(method->present_values(f));  // built, untimed
  const double setup_seconds = seconds_since(t0);
  write_all(
      a, in,
      [&](std::size_t k) {
        return segment(ktc_image(setup, method->reconstruct(frames[k])), rule);
      },
      fmt::format("{} at level {}: {}, noise {:g} of each value and {:g} of the largest, {}; "
                  "set-up {:.1f} s",
                  a.method, a.level, method->settings(), noise.relative, noise.floor,
                  rule.to_string(), setup_seconds));
}

}  // namespace

std::function<void()> add_ktc_command(CLI::App& app) {
  auto a = std::make_shared<KtcCommandArgs>();
  auto* cmd = app.add_subcommand(
      "ktc",
      "KTC2023's calling convention: reconstruct every dataN.mat of INPUT_FOLDER (with its "
      "ref.mat) at a difficulty LEVEL and write OUTPUT_FOLDER/N.mat (reconstruction: 256 x 256 "
      "uint8 classes); scores against trueN.mat where present");
  cmd->add_option("INPUT_FOLDER", a->input, "ref.mat and dataN.mat (trueN.mat optional)")
      ->required();
  cmd->add_option("OUTPUT_FOLDER", a->output, "where N.mat go (made if missing; not INPUT_FOLDER)")
      ->required();
  cmd->add_option("LEVEL", a->level,
                  "difficulty 1 ... 7: level k leaves out electrodes 1 ... 2(k-1)")
      ->required();
  cmd->add_option(
         "--method", a->method,
         "tikhonov | noser | laplace | smooth | greit | tv | gn | dnn | dnn-post (dnn: a learned "
         "model of the run --from names, from the frame; dnn-post: from a one-step image)")
      ->capture_default_str();
  cmd->add_option("--augment", a->augment,
                  "with --method dnn or dnn-post: the run's model trained with the tank's symmetry "
                  "group (group) or without (none)")
      ->capture_default_str();
  cmd->add_option("--from", a->from,
                  "a KTC run's folder (eitbench run --ktc): its tank, and the method's "
                  "regularisation and segmentation tuned on the training samples (--setting: "
                  "or on the run's simulated tanks, or both)");
  cmd->add_option("--setting", a->setting,
                  "with --from: the setting tuned on the training samples (samples), the one "
                  "tuned on the run's simulated tanks (simulation), or on both together, each "
                  "weighing one half (joint)")
      ->capture_default_str();
  cmd->add_option("--lambda", a->lambda,
                  "the regularisation on the method's relative scale (default: the run's, or what "
                  "the KTC run tuned on the training samples, docs/ktc.md)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--segmentation", a->segmentation,
                  "otsu (three-class Otsu, the challenge's baseline) | levels (--resistive and "
                  "--conductive fractions of the image's largest value); default: as --lambda");
  cmd->add_option("--resistive", a->resistive, "levels: the resistive class's fraction (0, 1]")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--conductive", a->conductive, "levels: the conductive class's fraction (0, 1]")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--electrode-coverage", a->coverage, "the rim's share under electrodes")
      ->capture_default_str();
  cmd->add_option("--density", a->density, "the tank's mesh: coarse | medium | fine")
      ->capture_default_str();
  cmd->add_option("--pixels", a->pixels, "the reconstruction's grid, pixels a side")
      ->capture_default_str();
  cmd->add_option("--noise-relative", a->noise.relative,
                  "the data term's noise: this share of each reference value (default: the "
                  "method's, as the run tuned it) ...");
  cmd->add_option("--noise-floor", a->noise.floor, "... and this share of the largest, combined")
      ->capture_default_str();
  cmd->add_flag("--quiet", a->quiet, "no progress or scores");
  return [a, cmd] { run(*a, *cmd); };
}

}  // namespace eitbench::cli
