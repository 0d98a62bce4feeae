#include "eitbench/bench/report/touch_report.h"

#include <fmt/core.h>

#include <array>
#include <cmath>
#include <functional>
#include <set>

#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/report/gnuplot.h"

namespace eitbench {
namespace {

bool same_snr(double a, double b) {
  return a == b || (std::isinf(a) && std::isinf(b));
}
std::string label(const ResultRow& r) {
  return r.augment == "-" ? r.method : r.method + " (" + r.augment + ")";
}
std::string dB(double snr) {
  return std::isfinite(snr) ? fmt::format("{:g} dB", snr) : "∞";
}
std::string fixed(double v, int digits = 3) {
  return std::isfinite(v) ? fmt::format("{:.{}f}", v, digits) : "—";
}
std::string percent(double v) {
  return std::isfinite(v) ? fmt::format("{:.0f} %", 100 * v) : "—";
}

// The rows at `snr` that were scored for touches, in the run's order.
std::vector<const ResultRow*> scored_at(const std::vector<ResultRow>& rows, double snr) {
  std::vector<const ResultRow*> out;
  for (const auto& r : rows)
    if (same_snr(r.snr_db, snr) && r.touch.frames > 0) out.push_back(&r);
  return out;
}

// "a, b (value)": every row whose `key` is best (higher when `higher`), NaN never best.
std::string best_by(const std::vector<const ResultRow*>& rows,
                    const std::function<double(const ResultRow&)>& key, bool higher,
                    const std::function<std::string(double)>& show) {
  double best = NAN;
  for (const ResultRow* r : rows) {
    const double v = key(*r);
    if (std::isfinite(v) && (std::isnan(best) || (higher ? v > best : v < best))) best = v;
  }
  if (std::isnan(best)) return "—";
  std::string names;
  for (const ResultRow* r : rows)
    if (key(*r) == best) names += (names.empty() ? "" : ", ") + label(*r);
  return fmt::format("{} ({})", names, show(best));
}

std::set<double, std::greater<double>> snrs_of(const std::vector<ResultRow>& rows) {
  std::set<double, std::greater<double>> s;
  for (const auto& r : rows)
    if (r.touch.frames > 0) s.insert(r.snr_db);
  return s;
}

bool signals_known(const std::vector<const ResultRow*>& rows) {
  for (const ResultRow* r : rows)
    if (!r->touch.by_signal.empty()) return true;
  return false;
}

void write_main_table(std::ostream& o, const std::vector<const ResultRow*>& rows) {
  const bool visible = signals_known(rows);
  o << "| method | threshold | count accuracy |" << (visible ? " count, every touch visible |" : "")
    << " centre error, median (× R) | centre error, p90 (× R) | radius error, median (× R) | "
       "missed / frame | phantom / frame |\n|---|---|---|"
    << (visible ? "---|" : "") << "---|---|---|---|---|\n";
  for (const ResultRow* r : rows) {
    const TouchScores& t = r->touch;
    o << fmt::format("| {} | {} | {} |", label(*r),
                     std::isfinite(t.threshold) ? fmt::format("{:g}", t.threshold) : "circles",
                     percent(t.count_accuracy));
    if (visible) o << " " << percent(t.visible_count_accuracy) << " |";
    o << fmt::format(" {} | {} | {} | {} | {} |\n", fixed(t.centre_error_median),
                     fixed(t.centre_error_p90), fixed(t.radius_error_median),
                     fixed(t.missed_per_frame, 2), fixed(t.phantom_per_frame, 2));
  }
}

std::string signal_bin(const TouchSignalScores& b) {
  if (b.from == 0) return fmt::format("< {:g} %", 100 * b.to);
  if (std::isinf(b.to)) return fmt::format("≥ {:g} %", 100 * b.from);
  return fmt::format("{:g} – {:g} %", 100 * b.from, 100 * b.to);
}

// The share of true touches found, by the share of its frame's change each carries.
void write_by_signal(std::ostream& o, const std::vector<const ResultRow*>& rows) {
  const ResultRow* first = nullptr;
  for (const ResultRow* r : rows)
    if (!r->touch.by_signal.empty()) first = first ? first : r;
  if (!first) return;
  const auto& bins = first->touch.by_signal;
  o << fmt::format(
      "\nHow visible the touches are: each true touch's share of its frame's change, "
      "‖v(all) − v(all but it)‖ / ‖v(all) − v(none)‖ on the reconstruction model. The model "
      "explains a frame only to within its own error (the reconstruction mesh against the finer "
      "one that made the frames: at the true circles, its misfit is {} of a noise-free test "
      "frame, median), so a faint touch is one no method on it can be expected to find. {} of {} "
      "test frames have every touch visible (≥ {:g} %); \"count, every touch visible\" above is "
      "the count accuracy on them. True touches found, by share:\n\n| method |",
      std::isfinite(first->touch.model_error_median)
          ? fmt::format("{:.1f} %", 100 * first->touch.model_error_median)
          : "unknown",
      first->touch.visible_frames, first->touch.frames, 100 * bins.back().from);
  for (const auto& b : bins) o << " " << signal_bin(b) << " (" << b.touches << ") |";
  o << "\n|---|";
  for (std::size_t k = 0; k < bins.size(); ++k) o << "---|";
  o << "\n";
  for (const ResultRow* r : rows) {
    o << "| " << label(*r) << " |";
    for (std::size_t k = 0; k < bins.size(); ++k) {
      const auto& b = r->touch.by_signal;
      const bool has = k < b.size() && b[k].touches > 0;
      o << " " << (has ? percent(static_cast<double>(b[k].found) / b[k].touches) : "—") << " |";
    }
    o << "\n";
  }
}

// Count accuracy and median centre error of each method at every SNR.
void write_snr_table(std::ostream& o, const std::vector<ResultRow>& rows) {
  const auto snrs = snrs_of(rows);
  o << "| method |";
  for (const char* what : {"count", "centre"})
    for (double s : snrs) o << " " << what << " " << dB(s) << " |";
  o << "\n|---|";
  for (std::size_t k = 0; k < 2 * snrs.size(); ++k) o << "---|";
  o << "\n";
  for (const auto& [m, a] : methods_in_order(rows)) {
    std::vector<const ResultRow*> by_snr;
    for (double s : snrs) {
      const ResultRow* found = nullptr;
      for (const auto& r : rows)
        if (r.method == m && r.augment == a && same_snr(r.snr_db, s) && r.touch.frames > 0)
          found = &r;
      by_snr.push_back(found);
    }
    o << "| " << (a == "-" ? m : m + " (" + a + ")") << " |";
    for (const ResultRow* r : by_snr)
      o << " " << (r ? percent(r->touch.count_accuracy) : "—") << " |";
    for (const ResultRow* r : by_snr)
      o << " " << (r ? fixed(r->touch.centre_error_median) : "—") << " |";
    o << "\n";
  }
}

// Count accuracy by the true number of touches, when the test frames hold more than one number.
void write_by_count(std::ostream& o, const std::vector<const ResultRow*>& rows) {
  std::set<int> counts;
  for (const ResultRow* r : rows)
    for (const auto& c : r->touch.by_count) counts.insert(c.touches);
  if (counts.size() < 2) return;
  o << "\nCount accuracy by the true number of touches a frame:\n\n| method |";
  for (int c : counts) o << " " << c << " |";
  o << "\n|---|";
  for (std::size_t k = 0; k < counts.size(); ++k) o << "---|";
  o << "\n";
  for (const ResultRow* r : rows) {
    o << "| " << label(*r) << " |";
    for (int c : counts) {
      double v = NAN;
      for (const auto& b : r->touch.by_count)
        if (b.touches == c) v = b.count_accuracy;
      o << " " << percent(v) << " |";
    }
    o << "\n";
  }
}

}  // namespace

bool has_touch_scores(const std::vector<ResultRow>& rows) {
  for (const auto& r : rows)
    if (r.touch.frames > 0) return true;
  return false;
}

std::string touch_ranking(const std::vector<ResultRow>& rows, double snr) {
  const auto at = scored_at(rows, snr);
  if (at.empty()) return "";
  const auto show_r = [](double v) { return fmt::format("{:.3f} R", v); };
  return fmt::format(
      "At {}, the best median centre error: {}; the best count accuracy: {}; the best CC: {}.",
      dB(snr),
      best_by(
          at, [](const ResultRow& r) { return r.touch.centre_error_median; }, false, show_r),
      best_by(
          at, [](const ResultRow& r) { return r.touch.count_accuracy; }, true, percent),
      best_by(
          at, [](const ResultRow& r) { return r.cc; }, true,
          [](double v) { return fmt::format("{:.3f}", v); }));
}

void write_touch_section(std::ostream& o, const std::vector<ResultRow>& rows, double snr) {
  const auto at = scored_at(rows, snr);
  if (at.empty()) return;
  o << "\n## Touches: where, how many, how large\n\n"
    << "Each image's touches are the blobs of its in-disk pixels at or above a threshold × the "
       "image's maximum (8-connected; the smallest blobs dropped), each a circle of the blob's "
       "area at its intensity-weighted centroid. The threshold is chosen for each method and SNR "
       "on validation frames: the best count accuracy, then the lowest median centre error. The "
       "found touches are matched one to one to the true circles: the most pairs within a gating "
       "distance, then the least total centre distance (the constants: `touch_metrics` under "
       "Configuration). Count accuracy: the share of frames with the true number of touches. "
       "Errors over the matched touches, as fractions of the sensor radius R; missed: true "
       "touches without a match; phantom: found touches without one. "
    << fmt::format("At {}, {} test frames:\n\n", dB(snr), at.front()->touch.frames);
  write_main_table(o, at);
  o << "\n" << touch_ranking(rows, snr) << "\n";
  write_by_count(o, at);
  write_by_signal(o, at);
  o << "\nCount accuracy and median centre error (× R) at each SNR:\n\n";
  write_snr_table(o, rows);
  o << "\n![The share of true touches found within a centre distance, by "
       "method](touch_centre_errors.png)\n";
}

bool draw_touch_figure(const std::vector<ResultRow>& rows, double snr, const std::string& path) {
  LinePlot plot;
  plot.title = "share of true touches found within a centre distance, " + dB(snr);
  plot.x_label = "centre error (x R, the sensor radius)";
  plot.y_label = "share of true touches";
  for (const ResultRow* r : scored_at(rows, snr)) {
    const TouchScores& t = r->touch;
    if (t.centre_error_quantiles.empty() || t.true_touches == 0) continue;
    PlotSeries s;
    s.label = s.key = label(*r);
    const double share = static_cast<double>(t.matched) / t.true_touches;
    s.x.push_back(0), s.y.push_back(0);  // from the origin: no touch is found within 0
    for (std::size_t q = 0; q < t.centre_error_quantiles.size(); ++q) {
      s.x.push_back(t.centre_error_quantiles[q]);
      s.y.push_back(share * static_cast<double>(q) / (t.centre_error_quantiles.size() - 1));
    }
    plot.series.push_back(s);
  }
  return write_plot(plot, path);
}

}  // namespace eitbench
