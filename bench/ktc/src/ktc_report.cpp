#include "eitbench/bench/ktc/ktc_report.h"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/support/machine.h"
#include "eitbench/bench/support/version.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

using nlohmann::json;

// The challenge's published totals over levels 1-7 (three targets a level, at most 21), on its
// evaluation set: what a KTC-equivalent total is set against.
struct Anchor {
  const char* who;
  double total;
};
constexpr Anchor kAnchors[] = {
    {"1st: learned post-processing of a linearised reconstruction", 15.24},
    {"fully learned U-Net", 15.13},
    {"conditional diffusion", 14.60},
    {"2nd place", 12.75},
    {"3rd place (model-based)", 12.45},
    {"the organisers' one-step baseline (smoothness prior, Otsu), rerun", 10.29},
};

json rule_json(const SegmentationRule& r) {
  return {{"kind", to_string(r.kind)}, {"resistive", r.resistive}, {"conductive", r.conductive}};
}

json choice_json(const KtcChoice& c) {
  return {{"lambda", c.lambda},
          {"noise_relative", c.noise_relative},
          {"segmentation", rule_json(c.rule)},
          {"tuning_score", c.tuning_score},
          {"nested", {{"otsu", c.nested_otsu}, {"levels", c.nested_levels}}}};
}

// Whether the setting tuned on every sample lies on its candidates' first or last value: a wider
// grid might do better, and the report says so.
bool on_the_edge(const KtcMethodResult& m) {
  const auto [low, high] = std::minmax_element(m.candidates.begin(), m.candidates.end());
  return m.best.lambda == *low || m.best.lambda == *high;
}

// Whether the run tuned the method's noise model, and the setting's words for it.
bool tuned_noise(const KtcMethodResult& m) {
  return std::any_of(m.candidate_noise.begin(), m.candidate_noise.end(),
                     [&](double n) { return n != m.candidate_noise.front(); });
}
std::string noise_words(const KtcMethodResult& m) {
  return tuned_noise(m) ? fmt::format(", noise {:g}", m.best.noise_relative) : "";
}

// The report's cell for the tuning on simulated tanks: the total and the setting they chose.
std::string simulation_cell(const KtcMethodResult& m) {
  if (m.tuned_on_simulation.empty()) return "—";
  const KtcChoice& c = m.simulation_choice;
  return fmt::format("{:.2f} (lambda {:.3g}{}, {})", ktc_total(m.tuned_on_simulation), c.lambda,
                     tuned_noise(m) ? fmt::format(", noise {:g}", c.noise_relative) : "",
                     c.rule.to_string());
}

// The report's cell for the tuning on the other samples and the tanks together: the total (each
// sample with its own setting, so no single setting to show).
std::string joint_cell(const KtcMethodResult& m) {
  return m.tuned_jointly.empty() ? "—" : fmt::format("{:.2f}", ktc_total(m.tuned_jointly));
}

// Per candidate, every sample and level: the total with Otsu and with the best levels rule.
json sweep_json(const KtcMethodResult& m) {
  std::vector<int> all;
  for (std::size_t s = 0; s < m.samples.size(); ++s) all.push_back(static_cast<int>(s));
  json out = json::array();
  for (std::size_t c = 0; c < m.candidates.size(); ++c) {
    const int only = static_cast<int>(c);
    out.push_back({{"lambda", m.candidates[c]},
                   {"noise_relative", m.candidate_noise[c]},
                   {"otsu", tune_ktc(m, all, KtcRules::otsu, only).tuning_score},
                   {"best_rule", tune_ktc(m, all, KtcRules::either, only).tuning_score}});
  }
  return out;
}

// How the run drew its tuning tanks (null where it drew none).
json tuning_json(const KtcRunResults::Tuning& t) {
  if (t.tanks == 0) return nullptr;
  return {{"tanks", t.tanks},
          {"seed", t.seed},
          {"density", to_string(t.tank.density)},
          {"size_factor", t.tank.size_factor},
          {"noise", t.noise}};
}

// Each sample's model misfit, and the tanks' noise it implies without that sample (null: none).
json misfit_json(const KtcRunResults& r) {
  json out = json::array();
  for (std::size_t k = 0; k < r.misfits.size(); ++k) {
    const double without = ktc_misfit_noise(r.misfits, k);
    out.push_back({{"sample", r.samples[k]},
                   {"relative", r.misfits[k].relative},
                   {"rms", r.misfits[k].rms},
                   {"values", r.misfits[k].values},
                   {"noise_without", std::isfinite(without) ? json(without) : json(nullptr)}});
  }
  return out;
}

// The tuning on simulated tanks (null for a method not so tuned): the tanks' count, the setting
// they chose and each sample's score with it.
json simulation_json(const KtcMethodResult& m) {
  if (m.simulated.empty() || m.simulated.front().empty()) return nullptr;
  return {{"tanks", m.simulated.front().front().size()},
          {"choice", choice_json(m.simulation_choice)},
          {"held_out", m.tuned_on_simulation},
          {"total_held_out", ktc_total(m.tuned_on_simulation)}};
}

// The tuning on the other samples and the tanks together (null for a method without tanks): each
// sample's setting and its score with it.
json joint_json(const KtcMethodResult& m) {
  if (m.tuned_jointly.empty()) return nullptr;
  json choices = json::array();
  for (const auto& c : m.joint_choice) choices.push_back(choice_json(c));
  return {{"weights", "the samples one half, the tanks the other"},
          {"choice", choice_json(m.joint_best)},
          {"in_sample", m.joint_in_sample},
          {"held_out_choices", choices},
          {"held_out", m.tuned_jointly},
          {"total_held_out", ktc_total(m.tuned_jointly)}};
}

json method_json(const KtcMethodResult& m) {
  json held = json::array();
  for (const auto& c : m.held_out_choice) held.push_back(choice_json(c));
  return {{"method", m.method},
          {"candidates", m.candidates},
          {"candidate_noise", m.candidate_noise},
          {"best", choice_json(m.best)},
          {"held_out_choices", held},
          {"in_sample", m.in_sample},
          {"held_out", m.held_out},
          {"held_out_otsu", m.held_out_otsu},
          {"total_held_out", ktc_total(m.held_out)},
          {"total_in_sample", ktc_total(m.in_sample)},
          {"total_held_out_otsu", ktc_total(m.held_out_otsu)},
          {"sweep", sweep_json(m)},
          {"simulation", simulation_json(m)},
          {"joint", joint_json(m)},
          {"on_the_grids_edge", on_the_edge(m)},
          {"median_ms", m.median_ms},
          {"setup_seconds", m.setup_seconds}};
}

json contrasts_json(const KtcContrasts& c) {
  return {{"resistive", c.resistive},
          {"conductive", c.conductive},
          {"relative_residual", c.relative_residual}};
}

json learned_json(const KtcLearnedResults& l) {
  json without = json::array(), arms = json::array();
  for (const auto& c : l.contrasts.without) without.push_back(contrasts_json(c));
  for (const KtcLearnedArm& a : l.arms)
    arms.push_back({{"network", a.network},
                    {"arm", a.arm},
                    {"model_file", std::filesystem::path(a.model_file).filename().string()},
                    {"training_frames", a.training_frames},
                    {"end", to_string(a.end)},
                    {"converged", converged(a.end)},
                    {"steps", a.steps},
                    {"doublings", a.doublings},
                    {"stage_best_validation_mse", a.stage_best},
                    {"training_seconds", a.training_seconds},
                    {"simulated_test", {{"cc", a.test_cc}, {"score", a.test_score}}},
                    {"scores", a.scores},
                    {"total", ktc_total(a.scores)},
                    {"median_ms", a.median_ms}});
  const KtcNetworkOptions& n = l.options.network;
  return {
      {"contrast_band",
       {{"resistive", {l.options.resistive_low, l.options.resistive_high}},
        {"conductive", {l.options.conductive_low, l.options.conductive_high}},
        {"best_fit_inside", contrasts_json(l.in_band)}}},
      {"contrasts_fitted", contrasts_json(l.contrasts.all)},
      {"contrasts_fitted_without_each_sample", without},
      {"noise", l.noise},
      {"simulated", {{"train", l.train}, {"validation", l.validation}, {"test", l.test}}},
      {"simulation_seconds", l.simulation_seconds},
      {"threshold", n.threshold},
      {"one_step", {{"method", l.options.one_step.method}, {"lambda", l.options.one_step.lambda}}},
      {"training",
       {{"steps", n.steps},
        {"batch_size", n.batch_size},
        {"learning_rate", n.learning_rate},
        {"patience", n.patience},
        {"seed", n.seed},
        {"max_doublings", l.options.rule.max_doublings},
        {"doubling_tolerance", l.options.rule.tolerance}}},
      {"arms", arms}};
}

json results_json(const KtcRunResults& r) {
  const KtcTankOptions& t = r.tank.options;
  json methods = json::array();
  for (const auto& m : r.methods) methods.push_back(method_json(m));
  std::vector<double> z(r.tank.contact_impedances.data(),
                        r.tank.contact_impedances.data() + r.tank.contact_impedances.size());
  return {{"kind", "ktc"},
          {"program", program_version()},
          {"machine", describe_machine()},
          {"data", r.options.data},
          {"samples", r.samples},
          {"levels", r.options.levels},
          {"grid", r.options.grid},
          {"noise",
           {{"relative", r.options.noise.relative},
            {"floor", r.options.noise.floor},
            {"sweep", r.options.noise_sweep}}},
          {"tank",
           {{"radius", t.radius},
            {"electrode_coverage", t.electrode_coverage},
            {"density", to_string(t.density)},
            {"size_factor", t.size_factor},
            {"background", r.tank.background},
            {"contact_impedances", z},
            {"relative_residual", r.tank.relative_residual},
            {"reference_hash", r.reference_hash},
            {"calibration_seconds", r.calibration_seconds}}},
          {"model_misfit", misfit_json(r)},
          {"tuning_tanks", tuning_json(r.tuning)},
          {"methods", methods},
          {"learned", learned_json(r.learned)}};
}

// How far the tank's model is from each labelled sample, and the tuning tanks' noise that would
// stand for it (the figures --tuning-noise can be set from).
std::string misfit_markdown(const KtcRunResults& r) {
  if (r.misfits.empty()) return "";
  auto mv = [](double v) { return std::isfinite(v) ? fmt::format("{:.2f}", 1e3 * v) : "none"; };
  std::string list, held;
  for (std::size_t k = 0; k < r.misfits.size(); ++k) {
    list += fmt::format("{}sample {} {:.1f} % ({:.2f} mV a value)", k == 0 ? "" : ", ",
                        r.samples[k], 100 * r.misfits[k].relative, 1e3 * r.misfits[k].rms);
    held += (k == 0 ? "" : ", ") + mv(ktc_misfit_noise(r.misfits, k));
  }
  return fmt::format(
      "The model of each sample's truth (at level 1, at the contrasts that fit that sample best) "
      "misses this share of its change: {}. A simulated tank lacks that error; white noise "
      "standing for it, the rms over the samples whose change the model explains more than half "
      "of, is {} mV a value, and with each sample held out in turn {} mV (--tuning-noise takes "
      "any of them).\n\n",
      list, mv(ktc_misfit_noise(r.misfits, r.misfits.size())), held);
}

// The learned rows' section: how they were trained, how each training ended, the simulated test
// split, and what the group changed.
std::string learned_markdown(const KtcLearnedResults& l) {
  std::ostringstream o;
  o << "\n## The learned models\n\n";
  const KtcLearnedOptions& b = l.options;
  o << fmt::format(
      "eitbench's network, trained on {} simulated tanks ({} to validate on, {} to test on) drawn "
      "on the calibrated tank: one to three resistive or conductive discs, polygons or blobs, "
      "each target's conductivity {:.3g}-{:.3g} times the water's (resistive) or {:.3g}-{:.3g} "
      "times (conductive), log-uniformly, with the noise of the reference's repeated patterns "
      "({:.2g} V a value); simulated in {:.0f} s. Each training frame is shown at a level drawn "
      "from 1 to 7, its missing values as 0: one network serves every level. \"group\" also "
      "trains on each tank under the tank's 8 symmetry elements, applied to full frames before "
      "the level's values are removed. The output is segmented at +-{:.2g}, fixed beforehand. "
      "Nothing is tuned on the samples. Seed {} (`--seed`: the tanks and the training).\n\n",
      l.train, l.validation, l.test, b.resistive_low, b.resistive_high, b.conductive_low,
      b.conductive_high, l.noise, l.simulation_seconds, b.network.threshold, b.network.seed);
  o << fmt::format(
      "The contrasts measured on the samples (their truths on the tank's mesh, the ratios whose "
      "simulated changes come nearest the measured ones): {:.3g} resistive and {:.3g} "
      "conductive (residual {:.0f} %)",
      l.contrasts.all.resistive, l.contrasts.all.conductive,
      100 * l.contrasts.all.relative_residual);
  if (!l.contrasts.without.empty()) {
    o << "; without each sample in turn";
    for (std::size_t k = 0; k < l.contrasts.without.size(); ++k)
      o << fmt::format("{} {:.3g} / {:.3g}", k == 0 ? "" : ",", l.contrasts.without[k].resistive,
                       l.contrasts.without[k].conductive);
  }
  o << fmt::format(
      ". A target's effect saturates far from the water's conductivity, so the fits scatter; "
      "inside the band the best pair ({:.3g} / {:.3g}) leaves {:.0f} % of the changes "
      "unexplained, against {:.0f} % at the best anywhere.\n\n",
      l.in_band.resistive, l.in_band.conductive, 100 * l.in_band.relative_residual,
      100 * l.contrasts.all.relative_residual);
  o << "| model | training frames | steps | ended | converged | best validation MSE per stage | "
       "training (s) | simulated test: CC | simulated test: KTC score | total on the samples "
       "|\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const KtcLearnedArm& a : l.arms) {
    std::string stages;
    for (double v : a.stage_best) stages += (stages.empty() ? "" : ", ") + fmt::format("{:.4g}", v);
    o << fmt::format("| {} {} | {} | {} | {} | {} | {} | {:.0f} | {:.3f} | {:.3f} | {:.2f} |\n",
                     a.network, a.arm, a.training_frames, a.steps, to_string(a.end),
                     converged(a.end) ? "yes" : "**no**", stages, a.training_seconds, a.test_cc,
                     a.test_score, ktc_total(a.scores));
  }
  if (l.options.trains("dnn-post"))
    o << fmt::format(
        "\ndnn-post reads a one-step image, {} at lambda {:g} (fixed beforehand) from the frame's "
        "present values, instead of the frame.\n",
        l.options.one_step.method, l.options.one_step.lambda);
  for (const std::string& network : l.options.networks) {
    const KtcLearnedArm* none = nullptr;
    const KtcLearnedArm* group = nullptr;
    for (const KtcLearnedArm& a : l.arms)
      if (a.network == network) (a.arm == "none" ? none : group) = &a;
    if (none && group)
      o << fmt::format(
          "\nThe group's effect on {}: total {:+.2f} on the samples ({:.2f} to {:.2f}), CC "
          "{:+.3f} on the simulated test split ({:.3f} to {:.3f}).\n",
          network, ktc_total(group->scores) - ktc_total(none->scores), ktc_total(none->scores),
          ktc_total(group->scores), group->test_cc - none->test_cc, none->test_cc, group->test_cc);
  }
  return o.str();
}

std::string report_markdown(const KtcRunResults& r) {
  std::ostringstream o;
  const std::size_t S = r.samples.size();
  o << "# KTC2023: reconstructions of the challenge's training samples\n\n";
  std::string levels;
  for (int l : r.options.levels) levels += (levels.empty() ? "" : ", ") + std::to_string(l);
  const auto machine = describe_machine();
  o << fmt::format("{} on {} ({} samples; levels {}); {}.\n\n", program_version(), r.options.data,
                   S, levels, machine.count("cpu") ? machine.at("cpu") : "");
  o << fmt::format(
      "The tank: radius {:.0f} mm, 32 electrodes covering {:.0f} % of the rim, calibrated to the "
      "empty tank's frame: sigma_0 {:.4g}, contact impedances {:.3g} to {:.3g}, relative "
      "residual {:.2f} % ({:.0f} s).\n\n",
      1e3 * r.tank.options.radius, 100 * r.tank.options.electrode_coverage, r.tank.background,
      r.tank.contact_impedances.minCoeff(), r.tank.contact_impedances.maxCoeff(),
      100 * r.tank.relative_residual, r.calibration_seconds);
  o << misfit_markdown(r);
  o << "Scores are the challenge's (mean SSIM of the resistive and conductive masks). Each "
       "sample is scored **held out**: with the regularisation and segmentation tuned on the "
       "other samples (every level), never on itself. The rule's kind, Otsu or levels, is "
       "chosen the same way within those samples (each tuned on all of them but one and scored "
       "on that one), so that a rule that only fits them better is not taken. The noise "
       "model (each value's standard deviation as a share of its reference value, beside the "
       "floor; \"noise\" in the setting) is tuned as the weight is, for every method but GREIT, "
       "whose image it does not change. Where the run had tuning tanks (--tuning-tanks), "
       "the methods of --tune-on-simulation are also tuned on them alone, the same way (the "
       "rule's kind nested): \"tuned on simulation\", every sample held out, with that "
       "setting; and on the other samples and the tanks together, the samples weighing one "
       "half and the tanks the other: \"samples and tanks\", every sample held out. A level's "
       "figure "
       "is the mean over the samples times 3, the challenge's three targets a level; the total "
       "over seven levels is at most 21.";
  if (r.tuning.tanks > 0)
    o << fmt::format(
        " This run tuned on {} tanks, each value's noise {:.3g} V ({}).", r.tuning.tanks,
        r.tuning.noise,
        r.options.tuning_noise > 0 ? "--tuning-noise" : "the reference's measured noise");
  o << "\n\n";
  o << "| method | L" << r.options.levels.front();
  for (std::size_t l = 1; l < r.options.levels.size(); ++l) o << " | L" << r.options.levels[l];
  o << " | total (held out) | tuned on simulation | samples and tanks | Otsu only (held out) | "
       "in sample | setting (all samples) | ms a frame | set-up a level (s) |\n|---";
  for (std::size_t l = 0; l < r.options.levels.size() + 8; ++l) o << "|---";
  o << "|\n";
  struct Row {
    double total;
    std::string text;
  };
  std::vector<Row> rows;
  for (const KtcMethodResult& m : r.methods) {
    std::string t = "| " + m.method;
    for (const auto& level : m.held_out) t += fmt::format(" | {:.2f}", ktc_level_total(level));
    double setup = 0;
    for (double s : m.setup_seconds) setup += s;
    t += fmt::format(
        " | **{:.2f}** | {} | {} | {:.2f} | {:.2f} | lambda {:.3g}{}{}, {} | {:.1f} | {:.1f} |\n",
        ktc_total(m.held_out), simulation_cell(m), joint_cell(m), ktc_total(m.held_out_otsu),
        ktc_total(m.in_sample), m.best.lambda, on_the_edge(m) ? " (edge)" : "", noise_words(m),
        m.best.rule.to_string(), m.median_ms,
        setup / static_cast<double>(std::max<std::size_t>(1, m.setup_seconds.size())));
    rows.push_back({ktc_total(m.held_out), t});
  }
  for (const KtcLearnedArm& a : r.learned.arms) {  // nothing tuned on the samples: one figure
    std::string t = "| " + a.network + " " + a.arm;
    for (const auto& level : a.scores) t += fmt::format(" | {:.2f}", ktc_level_total(level));
    t += fmt::format(
        " | **{:.2f}** | — | — | — | {:.2f} | trained in simulation{}{}, threshold {:.2g} | "
        "{:.1f} | — |\n",
        ktc_total(a.scores), ktc_total(a.scores), a.arm == "group" ? " with the group" : "",
        a.network == "dnn-post" ? ", on a one-step image" : "", r.learned.options.network.threshold,
        a.median_ms);
    rows.push_back({ktc_total(a.scores), t});
  }
  std::stable_sort(rows.begin(), rows.end(),
                   [](const Row& a, const Row& b) { return a.total > b.total; });
  for (const Row& row : rows) o << row.text;
  o << "\nThe challenge's published totals, on its evaluation set (other targets, scored blind; "
       "these samples are its training set):\n\n| entry | total of 21 |\n|---|---|\n";
  for (const Anchor& a : kAnchors) o << fmt::format("| {} | {:.2f} |\n", a.who, a.total);
  if (S < 2) o << "\nWith one sample there is nothing to hold out: its figures are in sample.\n";
  o << "\nTimes: one reconstruction from a frame's present values (milliseconds, the median at "
       "the setting), and building the method on a level's values once (seconds), each timed "
       "while another level ran beside it, one a core. \"(edge)\": the setting lies on its "
       "candidates' first or last value, and a wider grid might do better.\n";
  if (!r.learned.arms.empty()) o << learned_markdown(r.learned);
  if (can_draw_figures()) {
    o << "\n## Segmentations\n\nEach method with its setting tuned on every sample (water dark, "
         "resistive green, conductive yellow), the truth on top.\n\n";
    for (int level : r.options.levels)
      o << fmt::format("![Level {}](ktc_level{}.png)\n", level, level);
  }
  return o.str();
}

// The truth, then each method's segmentation at one level, samples side by side.
void draw_level(const KtcRunResults& r, std::size_t l, const std::string& path) {
  const PixelGrid ktc(kKtcImageSize, r.tank.options.radius);
  const PixelGrid grid(r.options.grid, r.tank.options.radius);  // the images'
  auto as_vector = [](const ClassImage& c) {
    return Eigen::Map<const Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1>>(c.data(), c.size())
        .cast<double>()
        .eval();
  };
  std::vector<ImageRow> rows;
  ImageRow truth{"truth", {}, 0, 2};
  for (const ClassImage& t : r.truths) truth.images.push_back(as_vector(t));
  rows.push_back(truth);
  for (const auto& m : r.methods) {
    ImageRow row{m.method, {}, 0, 2};
    for (const Eigen::VectorXd& image : m.images[l])
      row.images.push_back(as_vector(segment(to_ktc_grid(image, grid, {}), m.best.rule)));
    rows.push_back(row);
  }
  for (const KtcLearnedArm& a : r.learned.arms) {
    ImageRow row{a.network + " " + a.arm, {}, 0, 2};
    for (const ClassImage& c : a.classes[l]) row.images.push_back(as_vector(c));
    rows.push_back(row);
  }
  draw_image_grid_png(rows, ktc.mask(),
                      fmt::format("KTC level {}: samples {} ... {}", r.options.levels[l],
                                  r.samples.front(), r.samples.back()),
                      path, 128);
}

}  // namespace

void write_ktc_run(const KtcRunResults& r) {
  const std::filesystem::path out(r.options.out);  // the caller made it
  write_text_atomically((out / "results.json").string(),
                        [&](std::ostream& s) { s << results_json(r).dump(1) << '\n'; });
  write_text_atomically((out / "report.md").string(),
                        [&](std::ostream& s) { s << report_markdown(r); });
  if (!can_draw_figures() || (r.methods.empty() && r.learned.arms.empty())) return;
  for (std::size_t l = 0; l < r.options.levels.size(); ++l)
    draw_level(r, l, (out / fmt::format("ktc_level{}.png", r.options.levels[l])).string());
}

namespace {

// The settings of a KTC run's results.json, every field checked (InputError(path, field)).
KtcRunSettings parse_settings(const json& j, const std::string& path) {
  auto need = [&](const json& parent, const char* key, const std::string& where) -> const json& {
    if (!parent.is_object() || !parent.contains(key))
      throw InputError(path, where + key, "missing: not a KTC run's results (eitbench run --ktc)");
    return parent.at(key);
  };
  auto number = [&](const json& parent, const char* key, const std::string& where) {
    const json& v = need(parent, key, where);
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      throw InputError(path, where + key, "must be a finite number");
    return v.get<double>();
  };
  auto text = [&](const json& parent, const char* key, const std::string& where) {
    const json& v = need(parent, key, where);
    if (!v.is_string()) throw InputError(path, where + key, "must be text");
    return v.get<std::string>();
  };
  if (!j.is_object() || !j.contains("kind") || !j.at("kind").is_string() ||
      j.at("kind").get<std::string>() != "ktc")
    throw InputError(path, "kind", "is not a KTC run's results (eitbench run --ktc)");
  KtcRunSettings s;
  s.path = path;
  const json& tank = need(j, "tank", "");
  s.tank.radius = number(tank, "radius", "tank.");
  s.tank.electrode_coverage = number(tank, "electrode_coverage", "tank.");
  s.tank.size_factor = number(tank, "size_factor", "tank.");
  s.tank.density = parse_density(text(tank, "density", "tank."));
  s.background = number(tank, "background", "tank.");
  const json& z = need(tank, "contact_impedances", "tank.");
  if (!z.is_array() || z.size() != 32)
    throw InputError(path, "tank.contact_impedances", "must hold 32 numbers");
  s.contact_impedances.resize(32);
  for (int e = 0; e < 32; ++e) {
    const json& v = z[static_cast<std::size_t>(e)];
    if (!v.is_number() || !(v.get<double>() > 0) || !std::isfinite(v.get<double>()))
      throw InputError(path, "tank.contact_impedances", "must hold 32 positive, finite numbers");
    s.contact_impedances[e] = v.get<double>();
  }
  s.reference_hash = text(tank, "reference_hash", "tank.");
  const json& noise = need(j, "noise", "");
  s.noise.relative = number(noise, "relative", "noise.");
  s.noise.floor = number(noise, "floor", "noise.");
  const double grid = number(j, "grid", "");
  if (grid < 16 || grid > 256 || grid != std::floor(grid))
    throw InputError(path, "grid", "must be a whole number of pixels in 16 ... 256");
  s.grid = static_cast<int>(grid);
  const json& methods = need(j, "methods", "");
  if (!methods.is_array()) throw InputError(path, "methods", "must be a list");
  // A setting: `best`, or the choice of the tuning on simulated tanks (alone or with the samples).
  auto setting = [&](const json& c, const std::string& where) {
    KtcRunSettings::Method method;
    method.lambda = number(c, "lambda", where);
    if (!(method.lambda > 0)) throw InputError(path, where + "lambda", "must be positive");
    // Runs before the noise model was tuned used the run's for every method.
    method.noise_relative =
        c.contains("noise_relative") ? number(c, "noise_relative", where) : s.noise.relative;
    if (!KtcNoise{method.noise_relative, s.noise.floor}.valid())
      throw InputError(path, where + "noise_relative",
                       "must be zero or more, and not zero with noise.floor zero");
    const json& seg = need(c, "segmentation", where);
    method.rule.kind = parse_segmentation(text(seg, "kind", where + "segmentation."));
    method.rule.resistive = number(seg, "resistive", where + "segmentation.");
    method.rule.conductive = number(seg, "conductive", where + "segmentation.");
    method.rule.validate();
    return method;
  };
  for (const json& m : methods) {
    const std::string name = text(m, "method", "methods[].");
    const std::string where = "methods[" + name + "].";
    s.methods[name] = setting(need(m, "best", where), where + "best.");
    // Runs before the tuning on simulated tanks have none; a method not so tuned has null.
    if (m.contains("simulation") && !m.at("simulation").is_null())
      s.simulation_tuned[name] =
          setting(need(need(m, "simulation", where), "choice", where + "simulation."),
                  where + "simulation.choice.");
    // Runs before the tuning on samples and tanks together have none, as above.
    if (m.contains("joint") && !m.at("joint").is_null())
      s.joint_tuned[name] = setting(need(need(m, "joint", where), "choice", where + "joint."),
                                    where + "joint.choice.");
  }
  if (j.contains("learned")) {  // runs before the learned rows have none
    const json& arms = need(need(j, "learned", ""), "arms", "learned.");
    if (!arms.is_array()) throw InputError(path, "learned.arms", "must be a list");
    for (const json& a : arms) {
      const std::string arm = text(a, "arm", "learned.arms[].");
      // Runs before the post-processing network trained dnn only, and did not say so.
      const std::string network =
          a.contains("network") ? text(a, "network", "learned.arms[].") : "dnn";
      const std::string key = network + " " + arm;
      const std::string file = text(a, "model_file", "learned.arms[" + key + "].");
      if (arm != "none" && arm != "group")
        throw InputError(path, "learned.arms[].arm", "'" + arm + "' is none or group");
      if (network != "dnn" && network != "dnn-post")
        throw InputError(path, "learned.arms[].network", "'" + network + "' is dnn or dnn-post");
      if (file.empty() || std::filesystem::path(file).filename().string() != file)
        throw InputError(path, "learned.arms[" + key + "].model_file",
                         "must be a file name in the run's folder");
      s.models[key] = (std::filesystem::path(path).parent_path() / file).string();
    }
  }
  s.tank.validate();
  s.noise.validate();
  return s;
}

}  // namespace

KtcRunSettings read_ktc_settings(const std::string& run) {
  const std::string path = (std::filesystem::path(run) / "results.json").string();
  json j;
  try {
    j = json::parse(read_file_bytes(path));
  } catch (const json::exception& e) {
    throw InputError(path, "", std::string("is not JSON: ") + e.what());
  }
  try {
    return parse_settings(j, path);
  } catch (const InputError& e) {
    if (e.source() == path) throw;
    // A value the options refuse (a density, a rule, the tank): the file's, not a flag's.
    throw InputError(path, e.source() + (e.field().empty() ? "" : "." + e.field()), e.message());
  }
}

}  // namespace eitbench
