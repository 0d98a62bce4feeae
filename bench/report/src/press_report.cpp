#include "eitbench/bench/report/press_report.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "eitbench/bench/report/gnuplot.h"
#include "eitbench/bench/report/press_pick.h"

namespace eitbench {
namespace {

// Millimetres per mesh unit on the unit disk (configuration radius_mm); 0 when not given.
double unit_mm(const RunResults& r) {
  const auto it = r.configuration.find("radius_mm");
  return it == r.configuration.end() ? 0.0 : std::atof(it->second.c_str());
}

std::string length(double v, double mm) {
  if (std::isnan(v)) return "—";
  return mm > 0 ? fmt::format("{:.3f} ({:.1f} mm)", v, v * mm) : fmt::format("{:.3f}", v);
}

bool without_real_labels(const MeasuredRow& m) {
  // Real labels of the calibration set only (tuning, a fingerprint, a map), never trained on.
  return m.training == "none" || m.training.rfind("simulation", 0) == 0 ||
         m.training.rfind("calibration presses", 0) == 0 ||
         m.training.rfind("calibration frames", 0) == 0;
}

std::string name(const MeasuredRow& m) {
  return m.augment == "-" ? m.method : m.method + " (" + m.augment + ")";
}

void write_ranking(std::ostream& o, const std::vector<MeasuredRow>& rows, double mm) {
  std::vector<const MeasuredRow*> ranked;
  for (const auto& m : rows)
    if (without_real_labels(m)) ranked.push_back(&m);
  std::stable_sort(ranked.begin(), ranked.end(), [](const MeasuredRow* a, const MeasuredRow* b) {
    return a->centre_error_median < b->centre_error_median;
  });
  o << "| rank | method | tuned or trained on | median | mean | p90 | new positions: median | "
       "mean | within 0.5 R: mean | simulated median (x R) | real / simulated | ms a frame | "
       "settings |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  int rank = 0;
  for (const MeasuredRow* m : ranked) {
    const double drop = m->centre_error_fraction_of_radius / m->simulated_fraction_of_radius;
    o << fmt::format(
        "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", ++rank, name(*m),
        m->training.rfind("calibration presses", 0) == 0
            ? fmt::format("{} {}", m->finetune_n, m->training)
            : m->training,
        length(m->centre_error_median, mm), length(m->centre_error_mean, mm),
        length(m->centre_error_p90, mm), length(m->novel_centre_error_median, mm),
        length(m->novel_centre_error_mean, mm), length(m->inner_centre_error_mean, mm),
        std::isnan(m->simulated_fraction_of_radius)
            ? "—"
            : fmt::format("{:.3f}", m->simulated_fraction_of_radius),
        std::isnan(drop) ? "—" : fmt::format("{:.1f}x", drop),
        std::isnan(m->latency_median_ms) ? "—" : fmt::format("{:.3g}", m->latency_median_ms),
        m->settings.empty() ? "—" : m->settings);
  }
}

// The rows that used no label of any kind: each has its error in the simulation like the sensor.
std::vector<const MeasuredRow*> label_free(const std::vector<MeasuredRow>& rows) {
  std::vector<const MeasuredRow*> out;
  for (const auto& m : rows)
    if (!std::isnan(m.like_sensor_fraction_of_radius)) out.push_back(&m);
  return out;
}

const MeasuredRow* lowest(const std::vector<const MeasuredRow*>& rows, double MeasuredRow::*by) {
  const MeasuredRow* best = nullptr;
  for (const MeasuredRow* m : rows)
    if (!best || m->*by < best->*by) best = m;
  return best;
}

// The pick a user without labelled presses gets, and what it costs where labels exist.
void write_pick(std::ostream& o, const std::vector<MeasuredRow>& rows, double mm) {
  const std::vector<const MeasuredRow*> free = label_free(rows);
  if (free.empty()) return;
  const PressPick chosen = pick_without_labels(rows);
  const MeasuredRow* pick = chosen.pick;
  const MeasuredRow* best_free = lowest(free, &MeasuredRow::centre_error_median);
  std::vector<const MeasuredRow*> all;
  for (const auto& m : rows) all.push_back(&m);
  const MeasuredRow* best = lowest(all, &MeasuredRow::centre_error_median);
  o << "\n### A pick without labels\n\nThe rows that use no label of any kind, each tuned as "
       "its training says, scored first in the simulation like the sensor (simulated presses "
       "with the noise and channel gains measured on the calibration set's references, "
       "docs/real-presses.md), then on the real presses; median centre error.\n\n"
       "| method | tuned on | simulation like the sensor | real presses |\n|---|---|---|---|\n";
  for (const MeasuredRow* m : free)
    o << fmt::format("| {}{} | {} | {} | {} |\n", m == pick ? "**pick:** " : "", name(*m),
                     m->training, length(m->like_sensor_fraction_of_radius, mm),
                     length(m->centre_error_median, mm));
  if (!std::isnan(chosen.misfit_over_noise))
    o << fmt::format(
        "\nThe real frames' misfit to the model (GCV's estimate) is {:.1f} times the noise of the "
        "calibration set's references{}.\n",
        chosen.misfit_over_noise,
        chosen.real_frames_only
            ? fmt::format(
                  ": past {:g} times, the model's own error, which the simulation like the sensor "
                  "lacks, dominates it, so the pick keeps to the rows whose lambda the real "
                  "frames chose",
                  kModelErrorRatio)
            : "");
  o << fmt::format(
      "\nThe pick is **{}** ({}): {} median on the real presses. Regret against the best row "
      "without labels ({}, {}): **{}**; against the best row of all ({}, {}, {}): {}.\n",
      name(*pick), pick->training, length(pick->centre_error_median, mm), name(*best_free),
      best_free->training, length(pick->centre_error_median - best_free->centre_error_median, mm),
      name(*best), best->training, length(best->centre_error_median, mm),
      length(pick->centre_error_median - best->centre_error_median, mm));
}

const MeasuredRow* find(const std::vector<MeasuredRow>& rows, const std::string& augment,
                        const std::string& training, int n) {
  for (const auto& m : rows)
    if (m.method == "dnn" && m.augment == augment && m.training == training && m.finetune_n == n)
      return &m;
  return nullptr;
}

struct Way {
  const char* augment;
  const char* training;
  const char* label;
};
constexpr Way kWays[] = {{"none", "fine-tuned", "fine-tuned, plain"},
                         {"d16", "fine-tuned", "fine-tuned, d16 (x32)"},
                         {"none", "real presses only", "real presses only, plain"},
                         {"d16", "real presses only", "real presses only, d16 (x32)"}};

std::vector<int> finetune_sizes(const std::vector<MeasuredRow>& rows) {
  std::set<int> sizes;
  for (const auto& m : rows)
    if (m.training == "fine-tuned" || m.training == "real presses only") sizes.insert(m.finetune_n);
  return {sizes.begin(), sizes.end()};
}

void write_finetune(std::ostream& o, const std::vector<MeasuredRow>& rows, double mm) {
  const std::vector<int> sizes = finetune_sizes(rows);
  if (sizes.empty()) return;
  o << "\n### Few real labels\n\nMean centre error on all the measured presses, then on those at "
       "new positions, of the learned model trained on the calibration set's first n presses: "
       "fine-tuned from the model trained in simulation, or trained on the presses alone; each "
       "plain and with the x32 (d16) augmentation of those presses.\n\n| n |";
  for (const Way& w : kWays) o << " " << w.label << " |";
  o << "\n|---|---|---|---|---|\n";
  for (int n : sizes) {
    o << "| " << n << " |";
    for (const Way& w : kWays) {
      const MeasuredRow* m = find(rows, w.augment, w.training, n);
      o << " "
        << (m ? length(m->centre_error_mean, mm) + "; new " + length(m->novel_centre_error_mean, mm)
              : "—")
        << " |";
    }
    o << "\n";
  }
  std::string unconverged;
  for (const auto& m : rows)
    if (m.settings.find("not converged") != std::string::npos)
      unconverged += fmt::format("{}{} ({}, n = {})", unconverged.empty() ? "" : ", ", m.training,
                                 m.augment, m.finetune_n);
  if (!unconverged.empty())
    o << "\n**Not converged** (the step budget ran out before early stopping ended the training; "
         "`--finetune-steps` raises it): "
      << unconverged << ". Each row's training is in results.json's settings.\n";
  const std::string headline = finetune_headline(rows, mm);
  if (!headline.empty()) o << "\n" << headline << "\n";
  o << "\n![Error against labelled presses](press_finetune.png)\n";
}

}  // namespace

namespace {
// The fine-tuning's yardstick: the mean at new positions where the scored set has some (a model
// trained on a press at the same spot recalls it), else over all presses.
double yardstick(const MeasuredRow& m) {
  return m.novel_frames > 0 ? m.novel_centre_error_mean : m.centre_error_mean;
}
}  // namespace

std::string finetune_headline(const std::vector<MeasuredRow>& rows, double mm) {
  const std::vector<int> sizes = finetune_sizes(rows);
  if (sizes.empty()) return "";
  const std::string where = rows.front().novel_frames > 0
                                ? fmt::format(" at the {} new positions", rows.front().novel_frames)
                                : std::string();
  const MeasuredRow* plain = nullptr;  // the best unaugmented model at any size
  for (const auto& m : rows)
    if (m.method == "dnn" && m.augment == "none" &&
        (m.training == "fine-tuned" || m.training == "real presses only") &&
        (!plain || yardstick(m) < yardstick(*plain)))
      plain = &m;
  if (!plain) return "";
  for (int n : sizes)
    for (const char* training : {"fine-tuned", "real presses only"})
      if (const MeasuredRow* m = find(rows, "d16", training, n);
          m && yardstick(*m) <= yardstick(*plain))
        return fmt::format(
            "**{} augmented real presses ({}) match the best plain model ({} on {} presses): mean "
            "{} against {}{}.**",
            n, training, plain->training, plain->finetune_n, length(yardstick(*m), mm),
            length(yardstick(*plain), mm), where);
  return fmt::format(
      "No number of augmented real presses here matches the best plain model ({} on {} presses, "
      "mean {}{}).",
      plain->training, plain->finetune_n, length(yardstick(*plain), mm), where);
}

void write_press_section(std::ostream& o, const RunResults& r) {
  if (r.measured.empty()) return;
  const double mm = unit_mm(r);
  const MeasuredRow& first = r.measured.front();
  o << fmt::format(
      "\n## Real presses\n\nEvery method put each of the {} presses of **{}** where it found it; "
      "the centre error is the distance to the press's recorded centre, in the mesh's unit (the "
      "sensor's radius R = 1){}. Tuned on **{}** (another recording), never on the scored "
      "presses. {} of the scored presses lie at new positions, farther than 0.01 R from every "
      "calibration press: scores there ask whether a method generalises, not whether it recalls "
      "a spot it was tuned or trained on. {} lie within half the radius of the centre (the "
      "column within 0.5 R), far from every electrode, where a press changes the frame least. "
      "The simulated median is the same method's "
      "matched-touch centre error on the simulated test split (noise-free; four touches a "
      "frame), x R.\n\n",
      first.frames, first.scored,
      mm > 0 ? fmt::format(", with millimetres for R = {:g} mm", mm) : "", first.calibration,
      first.novel_frames, first.inner_frames);
  write_ranking(o, r.measured, mm);
  write_pick(o, r.measured, mm);
  write_finetune(o, r.measured, mm);
}

bool draw_press_figure(const RunResults& r, const std::string& path) {
  const std::vector<int> sizes = finetune_sizes(r.measured);
  if (sizes.empty()) return true;
  const double mm = unit_mm(r), scale = mm > 0 ? mm : 1.0;
  LinePlot plot;
  plot.title = r.measured.front().novel_frames > 0
                   ? "real presses at new positions: mean centre error against labelled presses"
                   : "real presses: mean centre error against labelled presses";
  plot.x_label = "labelled real presses (the calibration set's first n)";
  plot.y_label = mm > 0 ? "mean centre error (mm)" : "mean centre error (x R)";
  plot.log_x = true;
  // One colour per augmentation (the learned model's in every figure); dashed: from scratch.
  for (const Way& w : kWays) {
    PlotSeries s;
    s.label = w.label, s.points = true;
    s.key = std::string("dnn (") + w.augment + ")";
    s.dashed = std::string(w.training) == "real presses only";
    for (int n : sizes)
      if (const MeasuredRow* m = find(r.measured, w.augment, w.training, n))
        s.x.push_back(n), s.y.push_back(yardstick(*m) * scale);
    if (!s.x.empty()) plot.series.push_back(s);
  }
  // Flat lines: the floors, and the best model-based method (tuned on the calibration presses).
  const MeasuredRow* best = nullptr;
  for (const auto& m : r.measured)
    if (m.training == "calibration presses" && m.method != "fingerprint" &&
        (!best || yardstick(m) < yardstick(*best)))
      best = &m;
  for (const auto& m : r.measured)
    if (m.method == "centre" || m.method == "fingerprint" || &m == best) {
      PlotSeries s;
      s.label = m.method == "centre" ? "predicting the centre"
                                     : name(m) + " (tuned on the calibration presses)";
      s.key = m.method == "centre" ? "tikhonov" : m.method == "fingerprint" ? "shape" : m.method;
      s.dashed = true;
      s.x = {double(sizes.front()), double(sizes.back())};
      s.y = {yardstick(m) * scale, yardstick(m) * scale};
      plot.series.push_back(s);
    }
  return write_plot(plot, path);
}

}  // namespace eitbench
