#include "eitbench/bench/report/results.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

using nlohmann::json;

json number(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}
double number(const json& j) {
  return j.is_null() ? NAN : j.get<double>();
}

json snr_json(double snr) {
  return std::isfinite(snr) ? json(snr) : json("inf");
}
double snr_from(const json& j) {
  if (j.is_string() && j.get<std::string>() == "inf") return INFINITY;
  return j.get<double>();
}

}  // namespace

std::string snr_label(double snr_db) {
  return std::isfinite(snr_db) ? fmt::format("{:g}", snr_db) : "inf";
}

std::vector<std::pair<std::string, std::string>> methods_in_order(
    const std::vector<ResultRow>& rows) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& r : rows)
    if (std::find(out.begin(), out.end(), std::make_pair(r.method, r.augment)) == out.end())
      out.emplace_back(r.method, r.augment);
  return out;
}

// Per-frame scores at six decimals: enough for a paired test, a third of the file's digits.
json frame_scores_json(const std::vector<double>& scores) {
  json out = json::array();
  for (double v : scores) out.push_back(number(std::round(v * 1e6) / 1e6));
  return out;
}
std::vector<double> frame_scores_from_json(const json& x) {
  std::vector<double> out;
  for (const auto& v : x) out.push_back(number(v));
  return out;
}

json to_json(const ResultRow& x) {
  return {{"method", x.method},
          {"augment", x.augment},
          {"snr_db", snr_json(x.snr_db)},
          {"cc", number(x.cc)},
          {"re", number(x.re)},
          {"ssim", number(x.ssim)},
          {"mse", number(x.mse)},
          {"cc_std", number(x.cc_std)},
          {"re_std", number(x.re_std)},
          {"latency_median_ms", x.latency_median_ms},
          {"latency_p95_ms", x.latency_p95_ms},
          {"setup_s", x.setup_s},
          {"frames", x.frames},
          {"settings", x.settings},
          {"touch", to_json(x.touch)},
          {"frame_cc", frame_scores_json(x.frame_cc)},
          {"frame_re", frame_scores_json(x.frame_re)}};
}

ResultRow result_row_from_json(const json& x) {
  ResultRow row;
  row.method = x.at("method").get<std::string>();
  row.augment = x.at("augment").get<std::string>();
  row.snr_db = snr_from(x.at("snr_db"));
  row.cc = number(x.at("cc"));
  row.re = number(x.at("re"));
  row.ssim = number(x.at("ssim"));
  row.mse = number(x.at("mse"));
  row.cc_std = number(x.at("cc_std"));
  row.re_std = number(x.at("re_std"));
  row.latency_median_ms = x.at("latency_median_ms").get<double>();
  row.latency_p95_ms = x.at("latency_p95_ms").get<double>();
  row.setup_s = x.at("setup_s").get<double>();
  row.frames = x.at("frames").get<int>();
  row.settings = x.at("settings").get<std::string>();
  // Rows written before the touch metrics lack them: not scored.
  if (x.contains("touch")) row.touch = touch_scores_from_json(x.at("touch"));
  // Rows written before the per-frame scores were kept lack them.
  if (x.contains("frame_cc")) row.frame_cc = frame_scores_from_json(x.at("frame_cc"));
  if (x.contains("frame_re")) row.frame_re = frame_scores_from_json(x.at("frame_re"));
  return row;
}

json to_json(const TouchScores& t) {
  if (t.frames == 0) return nullptr;
  json by_count = json::array(), quantiles = json::array();
  for (const auto& c : t.by_count)
    by_count.push_back({{"touches", c.touches},
                        {"frames", c.frames},
                        {"count_accuracy", number(c.count_accuracy)},
                        {"centre_error_median", number(c.centre_error_median)}});
  for (double q : t.centre_error_quantiles) quantiles.push_back(number(q));
  json out = {{"frames", t.frames},
              {"threshold", number(t.threshold)},
              {"count_accuracy", number(t.count_accuracy)},
              {"centre_error_median", number(t.centre_error_median)},
              {"centre_error_p90", number(t.centre_error_p90)},
              {"radius_error_median", number(t.radius_error_median)},
              {"missed_per_frame", number(t.missed_per_frame)},
              {"phantom_per_frame", number(t.phantom_per_frame)},
              {"true_touches", t.true_touches},
              {"matched", t.matched},
              {"centre_error_quantiles", quantiles},
              {"by_count", by_count}};
  if (t.by_signal.empty()) return out;
  json by_signal = json::array();
  for (const auto& b : t.by_signal)
    by_signal.push_back(
        {{"from", b.from}, {"to", number(b.to)}, {"touches", b.touches}, {"found", b.found}});
  out["visible_frames"] = t.visible_frames;
  out["visible_count_accuracy"] = number(t.visible_count_accuracy);
  out["model_error_median"] = number(t.model_error_median);
  out["by_signal"] = by_signal;
  return out;
}

TouchScores touch_scores_from_json(const json& x) {
  TouchScores t;
  if (x.is_null()) return t;
  t.frames = x.at("frames").get<int>();
  t.threshold = number(x.at("threshold"));
  t.count_accuracy = number(x.at("count_accuracy"));
  t.centre_error_median = number(x.at("centre_error_median"));
  t.centre_error_p90 = number(x.at("centre_error_p90"));
  t.radius_error_median = number(x.at("radius_error_median"));
  t.missed_per_frame = number(x.at("missed_per_frame"));
  t.phantom_per_frame = number(x.at("phantom_per_frame"));
  t.true_touches = x.at("true_touches").get<int>();
  t.matched = x.at("matched").get<int>();
  for (const auto& q : x.at("centre_error_quantiles"))
    t.centre_error_quantiles.push_back(number(q));
  for (const auto& c : x.at("by_count"))
    t.by_count.push_back({c.at("touches").get<int>(), c.at("frames").get<int>(),
                          number(c.at("count_accuracy")), number(c.at("centre_error_median"))});
  if (!x.contains("by_signal")) return t;  // runs from before the signals were known
  t.visible_frames = x.at("visible_frames").get<int>();
  t.visible_count_accuracy = number(x.at("visible_count_accuracy"));
  t.model_error_median = number(x.at("model_error_median"));
  for (const auto& b : x.at("by_signal"))
    t.by_signal.push_back({b.at("from").get<double>(),
                           b.at("to").is_null() ? INFINITY : b.at("to").get<double>(),
                           b.at("touches").get<int>(), b.at("found").get<int>()});
  return t;
}

json to_json(const EfficiencyPoint& e) {
  return {{"augment", e.augment},
          {"budget", e.budget},
          {"train_size", e.train_size},
          {"steps", e.steps},
          {"epochs", e.epochs},
          {"test_mse", number(e.test_mse)},
          {"cc", number(e.cc)},
          {"re", number(e.re)},
          {"cc_std", number(e.cc_std)},
          {"re_std", number(e.re_std)},
          {"frames", e.frames},
          {"converged", e.converged},
          {"samples_seen", e.samples_seen},
          {"best_epoch", e.best_epoch},
          {"training_samples_per_second", e.training_samples_per_second},
          {"fraction_of_gemm_peak", e.fraction_of_gemm_peak}};
}

EfficiencyPoint efficiency_point_from_json(const json& e) {
  EfficiencyPoint p;
  p.augment = e.at("augment").get<std::string>();
  p.budget = e.at("budget").get<std::string>();
  p.train_size = e.at("train_size").get<int>();
  p.steps = e.at("steps").get<long long>();
  p.epochs = e.at("epochs").get<int>();
  p.test_mse = number(e.at("test_mse"));
  p.cc = number(e.at("cc"));
  p.re = number(e.at("re"));
  // Points written before the sweep trained to convergence lack these.
  p.converged = e.value("converged", false);
  p.samples_seen = e.value("samples_seen", 0LL);
  p.best_epoch = e.value("best_epoch", 0);
  p.training_samples_per_second = e.value("training_samples_per_second", 0.0);
  p.fraction_of_gemm_peak = e.value("fraction_of_gemm_peak", 0.0);
  // And these, before the figures drew error bars.
  p.cc_std = e.contains("cc_std") ? number(e.at("cc_std")) : 0.0;
  p.re_std = e.contains("re_std") ? number(e.at("re_std")) : 0.0;
  p.frames = e.value("frames", 0);
  return p;
}

json to_json(const MeasuredRow& m) {
  return {{"method", m.method},
          {"augment", m.augment},
          {"finetune_n", m.finetune_n},
          {"training", m.training},
          {"centre_error_median", number(m.centre_error_median)},
          {"centre_error_mean", number(m.centre_error_mean)},
          {"centre_error_p90", number(m.centre_error_p90)},
          {"centre_error_fraction_of_radius", number(m.centre_error_fraction_of_radius)},
          {"unit", m.unit},
          {"calibration", m.calibration},
          {"scored", m.scored},
          {"frames", m.frames},
          {"none_found", m.none_found},
          {"novel_frames", m.novel_frames},
          {"novel_centre_error_median", number(m.novel_centre_error_median)},
          {"novel_centre_error_mean", number(m.novel_centre_error_mean)},
          {"inner_frames", m.inner_frames},
          {"inner_centre_error_mean", number(m.inner_centre_error_mean)},
          {"latency_median_ms", number(m.latency_median_ms)},
          {"settings", m.settings},
          {"simulated_fraction_of_radius", number(m.simulated_fraction_of_radius)},
          {"like_sensor_fraction_of_radius", number(m.like_sensor_fraction_of_radius)},
          {"tuned_on_real_frames", m.tuned_on_real_frames},
          {"misfit_over_noise", number(m.misfit_over_noise)}};
}

MeasuredRow measured_row_from_json(const json& j) {
  MeasuredRow m;
  m.method = j.at("method").get<std::string>();
  m.augment = j.at("augment").get<std::string>();
  m.finetune_n = j.at("finetune_n").get<int>();
  m.training = j.at("training").get<std::string>();
  m.centre_error_median = number(j.at("centre_error_median"));
  m.centre_error_mean = number(j.at("centre_error_mean"));
  m.centre_error_p90 = number(j.at("centre_error_p90"));
  m.centre_error_fraction_of_radius = number(j.at("centre_error_fraction_of_radius"));
  m.unit = j.at("unit").get<std::string>();
  m.calibration = j.at("calibration").get<std::string>();
  m.scored = j.at("scored").get<std::string>();
  m.frames = j.at("frames").get<int>();
  m.none_found = j.at("none_found").get<int>();
  m.novel_frames = j.at("novel_frames").get<int>();
  m.novel_centre_error_median = number(j.at("novel_centre_error_median"));
  m.novel_centre_error_mean = number(j.at("novel_centre_error_mean"));
  // Absent from records made before the presses were split by where they lie.
  if (j.contains("inner_frames")) {
    m.inner_frames = j.at("inner_frames").get<int>();
    m.inner_centre_error_mean = number(j.at("inner_centre_error_mean"));
  }
  m.latency_median_ms = number(j.at("latency_median_ms"));
  m.settings = j.at("settings").get<std::string>();
  m.simulated_fraction_of_radius = number(j.at("simulated_fraction_of_radius"));
  // Absent from records made before the simulation like the sensor.
  if (j.contains("like_sensor_fraction_of_radius"))
    m.like_sensor_fraction_of_radius = number(j.at("like_sensor_fraction_of_radius"));
  // Absent from records made before the pick weighed the model's error.
  if (j.contains("tuned_on_real_frames"))
    m.tuned_on_real_frames = j.at("tuned_on_real_frames").get<bool>();
  if (j.contains("misfit_over_noise")) m.misfit_over_noise = number(j.at("misfit_over_noise"));
  return m;
}

json to_json(const TrainingSummary& t) {
  return {{"augment", t.augment},
          {"converged", t.converged},
          {"end", t.end},
          {"doublings", t.doublings},
          {"budget_steps", t.budget_steps},
          {"stage_best", t.stage_best},
          {"best_round", t.best_round},
          {"best_epoch", t.best_epoch},
          {"steps", t.steps},
          {"samples_seen", t.samples},
          {"seconds", t.seconds},
          {"training_samples_per_second", t.samples_per_second},
          {"fraction_of_gemm_peak", t.fraction_of_gemm_peak},
          {"inference_device", t.inference_device},
          {"device_latency_ms", t.device_latency_ms},
          {"device_frames_per_second", t.device_frames_per_second},
          {"history", json::parse(history_to_json(t.history))}};
}

// Files written before early stopping had "samples" and "samples_per_second" and no convergence
// flag: read as unconverged.
TrainingSummary training_summary_from_json(const json& t, const std::string& source) {
  TrainingSummary s;
  s.augment = t.at("augment").get<std::string>();
  s.converged = t.value("converged", false);
  // Runs from before the budget rule: one stage, its end told by the flag.
  s.end = t.value("end", std::string(s.converged ? "early stopping" : "budget"));
  s.doublings = t.value("doublings", 0);
  s.budget_steps = t.value("budget_steps", 0LL);
  s.stage_best = t.value("stage_best", std::vector<double>());
  s.best_epoch = t.at("best_epoch").get<int>();
  s.best_round = t.value("best_round", s.best_epoch);
  s.steps = t.at("steps").get<long long>();
  s.samples = t.contains("samples_seen") ? t.at("samples_seen").get<long long>()
                                         : t.at("samples").get<long long>();
  s.seconds = t.at("seconds").get<double>();
  s.samples_per_second = t.contains("training_samples_per_second")
                             ? t.at("training_samples_per_second").get<double>()
                             : t.at("samples_per_second").get<double>();
  s.fraction_of_gemm_peak = t.value("fraction_of_gemm_peak", 0.0);
  s.inference_device = t.value("inference_device", std::string());
  s.device_latency_ms = t.value("device_latency_ms", 0.0);
  s.device_frames_per_second = t.value("device_frames_per_second", 0.0);
  s.history = history_from_json(t.at("history").dump(), source);
  return s;
}

void write_results_json(const std::string& path, const RunResults& r) {
  json rows = json::array(), training = json::array(), efficiency = json::array(),
       measured = json::array();
  for (const auto& x : r.rows) rows.push_back(to_json(x));
  for (const auto& m : r.measured) measured.push_back(to_json(m));
  for (const auto& t : r.training) training.push_back(to_json(t));
  for (const auto& e : r.efficiency) efficiency.push_back(to_json(e));
  const json doc = {{"format", "eitbench-results-1"},
                    {"program", r.program},
                    {"configuration", r.configuration},
                    {"machine", r.machine},
                    {"results", rows},
                    {"training", training},
                    {"data_efficiency", efficiency},
                    {"measured", measured},
                    {"recommendation", r.recommendation}};
  write_text_atomically(path, [&](std::ostream& out) { out << doc.dump(2) << '\n'; });
}

RunResults read_results_json(const std::string& path) {
  return parse_results_json(read_file_bytes(path, 1LL << 30), path);
}

RunResults parse_results_json(const std::string& text, const std::string& path) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    throw InputError(path, "", std::string("not a valid results file: ") + e.what());
  }
  return parse_results_json(doc, path);
}

RunResults parse_results_json(const json& doc, const std::string& path) {
  RunResults r;
  std::string field = "";
  try {
    field = "format";
    if (doc.at("format").get<std::string>() != "eitbench-results-1")
      throw InputError(path, "format", "not an eitbench results file");
    field = "program";
    r.program = doc.at("program").get<std::string>();
    field = "configuration";
    r.configuration = doc.at("configuration").get<std::map<std::string, std::string>>();
    field = "machine";
    r.machine = doc.at("machine").get<std::map<std::string, std::string>>();
    field = "results";
    for (const auto& x : doc.at("results")) {
      r.rows.push_back(result_row_from_json(x));
      const ResultRow& row = r.rows.back();
      for (const auto* scores : {&row.frame_cc, &row.frame_re})
        if (!scores->empty() && scores->size() != static_cast<std::size_t>(row.frames))
          throw InputError(
              path,
              fmt::format("results[{}].frame_{}", r.rows.size() - 1,
                          scores == &row.frame_cc ? "cc" : "re"),
              fmt::format("holds {} scores for {} frames", scores->size(), row.frames));
    }
    field = "training";
    for (const auto& t : doc.at("training"))
      r.training.push_back(training_summary_from_json(t, path));
    field = "data_efficiency";
    for (const auto& e : doc.at("data_efficiency"))
      r.efficiency.push_back(efficiency_point_from_json(e));
    field = "measured";  // absent in runs from before real presses were scored
    if (doc.contains("measured"))
      for (const auto& m : doc.at("measured")) r.measured.push_back(measured_row_from_json(m));
    field = "recommendation";
    r.recommendation = doc.at("recommendation").get<std::string>();
  } catch (const json::exception& e) {
    throw InputError(path, field, std::string("not a valid results file: ") + e.what());
  }
  return r;
}

void write_results_csv(const std::string& path, const std::vector<ResultRow>& rows) {
  write_text_atomically(path, [&](std::ostream& out) {
    out << "method,augment,snr_db,cc,re,ssim,mse,latency_median_ms,latency_p95_ms,setup_s,cc_std,"
           "re_std,frames,settings,touch_threshold,count_accuracy,centre_error_median,"
           "centre_error_p90,radius_error_median,missed_per_frame,phantom_per_frame\n";
    out << std::setprecision(8);
    for (const auto& r : rows) {
      std::string settings = r.settings;
      for (char& c : settings)
        if (c == '"') c = '\'';
      out << r.method << ',' << r.augment << ',' << snr_label(r.snr_db) << ',' << r.cc << ','
          << r.re << ',' << r.ssim << ',' << r.mse << ',' << r.latency_median_ms << ','
          << r.latency_p95_ms << ',' << r.setup_s << ',' << r.cc_std << ',' << r.re_std << ','
          << r.frames << ",\"" << settings << '"';
      const TouchScores& t = r.touch;
      if (t.frames > 0)
        out << ',' << t.threshold << ',' << t.count_accuracy << ',' << t.centre_error_median << ','
            << t.centre_error_p90 << ',' << t.radius_error_median << ',' << t.missed_per_frame
            << ',' << t.phantom_per_frame << '\n';
      else
        out << ",,,,,,,\n";  // not scored: empty cells, not numbers
    }
  });
}

}  // namespace eitbench
