#include "eitbench/bench/report/report.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/report/efficiency.h"
#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/report/press_report.h"
#include "eitbench/bench/report/touch_report.h"

namespace eitbench {
namespace {

std::string label(const ResultRow& r) {
  return r.augment == "-" ? r.method : r.method + " (" + r.augment + ")";
}

// The SNRs of the rows, noise-free first, then from the highest.
std::vector<double> snrs_of(const std::vector<ResultRow>& rows) {
  std::set<double> s;
  for (const auto& r : rows) s.insert(r.snr_db);
  std::vector<double> out(s.rbegin(), s.rend());
  return out;
}

const ResultRow* find(const std::vector<ResultRow>& rows, const std::string& method,
                      const std::string& augment, double snr) {
  for (const auto& r : rows)
    if (r.method == method && r.augment == augment &&
        (r.snr_db == snr || (std::isinf(r.snr_db) && std::isinf(snr))))
      return &r;
  return nullptr;
}

std::string fixed(double v, int digits = 3) {
  return std::isfinite(v) ? fmt::format("{:.{}f}", v, digits) : "—";
}
std::string ms(double v) {
  return v >= 10 ? fmt::format("{:.1f}", v) : fmt::format("{:.3g}", v);
}
std::string dB(double snr) {
  return std::isfinite(snr) ? fmt::format("{:g} dB", snr) : "∞";
}

}  // namespace

namespace {

// " Not converged: ..." for the learned models the budget stopped, or nothing.
std::string unconverged_note(const std::vector<TrainingSummary>& training) {
  std::string names;
  int count = 0;
  for (const auto& t : training)
    if (!t.converged) names += (count++ ? ", " : "") + ("dnn (" + t.augment + ")");
  if (count == 0) return "";
  const bool one = count == 1;
  return " **Not converged:** " + names + (one ? " was" : " were") +
         " ended by the training budget or the schedule's floor, not by the model (the training "
         "table says which), so this ranking may understate " +
         (one ? "it" : "them") + " (raise the budget: `--epochs`, `--doublings`).";
}

}  // namespace

std::string recommend(const std::vector<ResultRow>& rows,
                      const std::vector<TrainingSummary>& training) {
  return recommend(rows) + unconverged_note(training);
}

double headline_snr(const std::vector<ResultRow>& rows) {
  const auto snrs = snrs_of(rows);
  if (snrs.empty()) return NAN;
  return std::find(snrs.begin(), snrs.end(), 40.0) != snrs.end() ? 40.0 : snrs.front();
}

std::string recommend(const std::vector<ResultRow>& rows) {
  constexpr double kClearlyFaster = 1.5;
  if (rows.empty()) return "No results.";
  const double snr = headline_snr(rows);
  std::vector<const ResultRow*> at;
  for (const auto& r : rows)
    if (r.snr_db == snr || (std::isinf(r.snr_db) && std::isinf(snr))) at.push_back(&r);
  auto faster = [](const ResultRow* a, const ResultRow* b) {
    return a->latency_median_ms < b->latency_median_ms;
  };
  const ResultRow* fastest = *std::min_element(at.begin(), at.end(), faster);
  std::vector<const ResultRow*> scored;
  for (const ResultRow* r : at)
    if (r->frames > 0 && std::isfinite(r->cc)) scored.push_back(r);
  if (scored.empty())
    return fmt::format(
        "The data carry no labels, so quality cannot be ranked here: judge the images in "
        "reconstructions.png. The fastest method is {} ({} ms a frame).",
        label(*fastest), ms(fastest->latency_median_ms));
  const ResultRow* best = *std::max_element(scored.begin(), scored.end(),
                                            [](auto* a, auto* b) { return a->cc < b->cc; });
  // A method within 0.02 CC of the best replaces it only when clearly faster: one-frame timings
  // of a few tenths of a millisecond (a GPU's) differ by more than their noise only at a ratio.
  const ResultRow* pick = best;
  for (const ResultRow* r : scored)
    if (r->cc >= best->cc - 0.02 &&
        r->latency_median_ms * kClearlyFaster <= best->latency_median_ms &&
        r->latency_median_ms < pick->latency_median_ms)
      pick = r;
  std::string text = fmt::format(
      "Pick **{}**: CC {:.3f}, RE {:.3f} at {}, {} ms a frame (median), set up in {:.3g} s.",
      label(*pick), pick->cc, pick->re, dB(snr), ms(pick->latency_median_ms), pick->setup_s);
  if (pick != best)
    text += fmt::format(
        " The best CC, {:.3f}, is {}'s, but it takes {} ms a frame, {:.0f}× longer, for {:.3f} "
        "more CC: within the 0.02 that separates methods here, the faster one wins.",
        best->cc, label(*best), ms(best->latency_median_ms),
        best->latency_median_ms / std::max(pick->latency_median_ms, 1e-9), best->cc - pick->cc);
  else
    text += fmt::format(
        " It has the best CC of all methods, and no method within 0.02 of it is {:g}× faster.",
        kClearlyFaster);
  if (fastest != pick)
    text += fmt::format(" Where every microsecond counts, {} takes {} ms a frame (CC {:.3f}).",
                        label(*fastest), ms(fastest->latency_median_ms), fastest->cc);
  return text;
}

namespace {

using Methods = std::vector<std::pair<std::string, std::string>>;

void write_header(std::ostream& o, const RunResults& r) {
  auto machine = [&](const char* key) { return r.machine.count(key) ? r.machine.at(key) : "?"; };
  o << "# eitbench benchmark report\n\n";
  o << fmt::format("{} on {} ({} cores, {}), {}; BLAS {}; LibTorch threads {}; GPU {}.\n\n",
                   r.program, machine("cpu"), machine("cores"), machine("memory"), machine("os"),
                   machine("blas"), machine("torch_threads"), machine("gpu"));
  o << "## Which reconstructor to pick\n\n" << r.recommendation << "\n\n";
}

// A table header: the first column, then `prefix` at each SNR for each prefix.
void write_snr_header(std::ostream& o, const std::string& first,
                      const std::vector<std::string>& prefixes, const std::vector<double>& snrs) {
  o << "| " << first << " |";
  for (const auto& prefix : prefixes)
    for (double s : snrs) o << " " << prefix << " " << dB(s) << " |";
  o << "\n|---|";
  for (std::size_t k = 0; k < prefixes.size() * snrs.size(); ++k) o << "---|";
  o << "\n";
}

void write_quality(std::ostream& o, const RunResults& r, const Methods& methods,
                   const std::vector<double>& snrs) {
  o << "## Quality (the paper's Table I, for every method)\n\n";
  o << "Mean over the test frames; the hyperparameter of each model-based method is chosen on the "
       "validation split at the same SNR.\n\n";
  write_snr_header(o, "method", {"CC", "RE"}, snrs);
  for (const auto& [m, a] : methods) {
    o << "| " << (a == "-" ? m : m + " (" + a + ")") << " |";
    for (const bool cc : {true, false})
      for (double s : snrs) {
        const ResultRow* x = find(r.rows, m, a, s);
        o << " " << fixed(x ? (cc ? x->cc : x->re) : NAN) << " |";
      }
    o << "\n";
  }
}

void write_augmentation_gain(std::ostream& o, const RunResults& r, const Methods& methods,
                             const std::vector<double>& snrs) {
  bool any_dnn = false;
  for (const auto& [m, a] : methods) any_dnn |= m == "dnn" && a != "none";
  if (!any_dnn || !find(r.rows, "dnn", "none", snrs.front())) return;
  o << "\n**Augmentation's relative improvement** over the learned reconstructor trained "
       "without it (the paper reports CC +12.8 to +17.4 % and RE −21.2 to −23.7 %):\n\n";
  write_snr_header(o, "augment", {"ΔCC", "ΔRE"}, snrs);
  for (const auto& [m, a] : methods) {
    if (m != "dnn" || a == "none") continue;
    o << "| " << a << " |";
    for (const bool cc : {true, false})
      for (double s : snrs) {
        const ResultRow *x = find(r.rows, m, a, s), *base = find(r.rows, "dnn", "none", s);
        const double v =
            x && base ? 100.0 * ((cc ? x->cc : x->re) / (cc ? base->cc : base->re) - 1) : NAN;
        o << " " << (std::isfinite(v) ? fmt::format("{:+.1f} %", v) : "—") << " |";
      }
    o << "\n";
  }
}

void write_runtime(std::ostream& o, const RunResults& r, const Methods& methods,
                   const std::vector<double>& snrs) {
  o << "\n## Runtime\n\nSetup: for model-based methods the Jacobian, the pixel map and the "
       "hyperparameter choice; for the learned reconstructor, its training. Per frame: wall clock "
       "of one frame at a time.";
  const auto learned_device = r.configuration.find("learned_device");
  if (learned_device != r.configuration.end())
    o << fmt::format(
        " The learned reconstructor ran on {}, where it trained; the model-based "
        "methods on the CPU.",
        learned_device->second);
  o << "\n\n| method | setup (s) | per frame, median (ms) | p95 (ms) | frames/s |\n"
       "|---|---|---|---|---|\n";
  for (const auto& [m, a] : methods) {
    const ResultRow* x = find(r.rows, m, a, snrs.front());
    if (!x) continue;
    o << fmt::format("| {} | {:.3g} | {} | {} | {:.0f} |\n", label(*x), x->setup_s,
                     ms(x->latency_median_ms), ms(x->latency_p95_ms),
                     1000.0 / std::max(x->latency_median_ms, 1e-9));
  }
}

// Inference on the GPU the models trained on (the runtime table above is the CPU's).
void write_device_inference(std::ostream& o, const RunResults& r) {
  bool any = false;
  for (const auto& t : r.training) any |= !t.inference_device.empty();
  if (!any) return;
  o << "\n### Inference on the GPU\n\nWall clock, frames from host memory and images back "
       "to it, after a warm-up: one frame at a time (median of 200), and batches of 1,000 "
       "frames.\n\n| augment | device | one frame (ms) | batches of 1,000 (frames/s) |\n"
       "|---|---|---|---|\n";
  for (const auto& t : r.training)
    if (!t.inference_device.empty())
      o << fmt::format("| {} | {} | {:.3f} | {:.0f} |\n", t.augment, t.inference_device,
                       t.device_latency_ms, t.device_frames_per_second);
}

void write_training(std::ostream& o, const RunResults& r) {
  if (r.training.empty()) return;
  o << "\n## Training\n\nEach learned model trains with its budget, then continues from its "
       "best model with a fresh schedule over as many steps again (the budget doubles) while the "
       "last doubling lowered its best validation MSE by more than the tolerance, up to the run's "
       "doublings; within each stage early stopping ends it when validation stops improving. "
       "Converged: the model ended the training (early stopping with the learning rate at least "
       "a tenth of the cosine's range above its floor, or a doubling, run down to its floor, "
       "that no longer paid); **no**: the budget, early stopping in the cosine's last fifth or "
       "at the floor with no doubling to tell whether the schedule ended it, or the cap on "
       "doublings while the last one still paid.\n\n"
       "| augment | converged | budget (steps) | last doubling | steps | samples seen | "
       "best epoch | best validation MSE | samples/s | of GEMM peak | time (s) |\n"
       "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& t : r.training) {
    const double best = t.best_round > 0 && t.best_round <= static_cast<int>(t.history.size())
                            ? t.history[t.best_round - 1].validation_loss
                            : NAN;
    // The CPU's GEMM peak is measured only for CPU training; a GPU run has none to compare with.
    const std::string of_peak = t.fraction_of_gemm_peak > 0
                                    ? fmt::format("{:.0f} %", 100 * t.fraction_of_gemm_peak)
                                    : std::string("–");
    // What the last doubling changed: the best validation MSE after it against before it.
    const std::size_t k = t.stage_best.size();
    const std::string last =
        k >= 2 ? fmt::format("{:+.1f} %", 100 * (t.stage_best[k - 1] / t.stage_best[k - 2] - 1))
               : std::string("–");
    o << fmt::format("| {} | {} | {} | {} | {} | {} | {} | {:.4g} | {:.0f} | {} | {:.1f} |\n",
                     t.augment, t.converged ? "yes (" + t.end + ")" : "**no** (" + t.end + ")",
                     t.budget_steps > 0 ? std::to_string(t.budget_steps) : std::string("–"), last,
                     t.steps, t.samples, t.best_epoch, best, t.samples_per_second, of_peak,
                     t.seconds);
  }
  o << "\n![Training (light) and validation MSE against samples seen](loss_curves.png)\n";
  write_device_inference(o, r);
}

}  // namespace

void write_report(const std::string& path, const RunResults& r) {
  std::ostringstream o;
  const auto snrs = snrs_of(r.rows);
  const auto methods = methods_in_order(r.rows);
  write_header(o, r);
  write_quality(o, r, methods, snrs);
  write_augmentation_gain(o, r, methods, snrs);
  write_touch_section(o, r.rows, headline_snr(r.rows));
  write_runtime(o, r, methods, snrs);
  write_training(o, r);
  write_efficiency_section(o, r.efficiency);
  write_press_section(o, r);
  o << "\n## Reconstructions\n\n![The first test samples: truth, then each "
       "method](reconstructions.png)\n";
  o << "\n## Configuration\n\n| | |\n|---|---|\n";
  for (const auto& [k, v] : r.configuration) o << "| " << k << " | " << v << " |\n";
  o << "\nEvery figure is in results.json (and results.csv, one row per method × augmentation × "
       "SNR). Compare two runs with `eitbench compare OLD/results.json NEW/results.json`; re-draw "
       "this report from them with `eitbench report FOLDER`.\n";
  write_text_atomically(path, [&](std::ostream& out) { out << o.str(); });
}

std::string summary_table(const RunResults& r) {
  const auto snrs = snrs_of(r.rows);
  std::string out = fmt::format("{:<18}", "method");
  for (double s : snrs) out += fmt::format("{:>9}", "CC " + snr_label(s));
  // RE noise-free and at the worst SNR; one column when there is one SNR (measured frames).
  const bool two_re = snrs.size() > 1;
  out += fmt::format("{:>9}", "RE " + snr_label(snrs.front()));
  if (two_re) out += fmt::format("{:>9}", "RE " + snr_label(snrs.back()));
  out += fmt::format("{:>12}{:>10}\n", "ms/frame", "setup s");
  for (const auto& [m, a] : methods_in_order(r.rows)) {
    out += fmt::format("{:<18}", a == "-" ? m : m + " " + a);
    for (double s : snrs) {
      const ResultRow* x = find(r.rows, m, a, s);
      out += fmt::format("{:>9}", x ? fixed(x->cc) : "—");
    }
    const ResultRow *first = find(r.rows, m, a, snrs.front()),
                    *last = find(r.rows, m, a, snrs.back());
    out += fmt::format("{:>9}", first ? fixed(first->re) : "—");
    if (two_re) out += fmt::format("{:>9}", last ? fixed(last->re) : "—");
    out += fmt::format("{:>12}{:>10.3g}\n", first ? ms(first->latency_median_ms) : "—",
                       first ? first->setup_s : NAN);
  }
  return out;
}

}  // namespace eitbench
