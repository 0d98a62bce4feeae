#include "eitbench/bench/report/efficiency.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <set>

#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/report/gnuplot.h"

namespace eitbench {
namespace {

struct Line {
  const char* augment;
  const char* budget;
  const char* label;
  const char* key;  // the method's colour in every figure
  bool dashed;
};
constexpr Line kLines[] = {{"none", "converged", "none, converged", "dnn (none)", false},
                           {"d16", "converged", "d16, converged", "dnn (d16)", false},
                           {"d16", "equal_steps", "d16, none's steps", "dnn (d16)", true}};

const EfficiencyPoint* find(const std::vector<EfficiencyPoint>& points, const std::string& augment,
                            const std::string& budget, int n) {
  for (const auto& p : points)
    if (p.augment == augment && p.budget == budget && p.train_size == n) return &p;
  return nullptr;
}

// Error bars: the standard error of the mean over the test frames, where the run kept it.
bool draw_metric(const std::vector<EfficiencyPoint>& points, bool cc, const std::string& path) {
  LinePlot plot;
  plot.title = cc ? "test CC against training-set size (mean +- standard error over test frames)"
                  : "test RE against training-set size (mean +- standard error over test frames)";
  plot.x_label = "training frames (before augmentation)";
  plot.y_label = cc ? "CC (correlation with the true image)" : "RE (relative error)";
  plot.log_x = true;
  for (const Line& line : kLines) {
    PlotSeries s;
    s.label = line.label, s.key = line.key, s.dashed = line.dashed, s.points = true;
    bool bars = true;
    for (const auto& p : points)
      if (p.augment == line.augment && p.budget == line.budget) {
        const double mean = cc ? p.cc : p.re, sd = cc ? p.cc_std : p.re_std;
        const double se = p.frames > 0 ? sd / std::sqrt(double(p.frames)) : 0.0;
        s.x.push_back(p.train_size), s.y.push_back(mean);
        s.low.push_back(mean - se), s.high.push_back(mean + se);
        bars = bars && p.frames > 0;
      }
    if (!bars) s.low.clear(), s.high.clear();
    if (!s.x.empty()) plot.series.push_back(s);
  }
  return write_plot(plot, path);
}

std::set<int> sizes_of(const std::vector<EfficiencyPoint>& points) {
  std::set<int> sizes;
  for (const auto& p : points) sizes.insert(p.train_size);
  return sizes;
}

std::string cell(const EfficiencyPoint* p) {
  if (!p) return "—";
  return fmt::format("{:.3f} / {:.3f} ({} steps{})", p->cc, p->re, p->steps,
                     p->converged || p->budget == "equal_steps" ? "" : ", **not converged**");
}

}  // namespace

std::string efficiency_headline(const std::vector<EfficiencyPoint>& points) {
  const std::set<int> sizes = sizes_of(points);
  if (sizes.empty()) return "";
  const int largest = *sizes.rbegin();
  const EfficiencyPoint* target = find(points, "none", "converged", largest);
  if (!target || !std::isfinite(target->cc)) return "";
  for (int n : sizes) {
    const EfficiencyPoint* d16 = find(points, "d16", "converged", n);
    if (d16 && d16->cc >= target->cc)
      return fmt::format(
          "D16 on {} frames reaches the CC that no augmentation reaches on {} ({:.3f} against "
          "{:.3f}): {:.3g}x fewer frames (the paper: 700 augmented frames match 21,833 plain "
          "ones, 31x).",
          n, largest, d16->cc, target->cc, double(largest) / n);
  }
  return fmt::format(
      "D16 does not reach no augmentation's CC on {} frames ({:.3f}) at any smaller size of the "
      "sweep.",
      largest, target->cc);
}

void write_efficiency_section(std::ostream& o, const std::vector<EfficiencyPoint>& points) {
  if (points.empty()) return;
  o << "\n## Data efficiency (the paper's Fig. 8)\n\n"
    << efficiency_headline(points)
    << "\n\nAt each size n, no augmentation trains on n training frames drawn at random "
       "(nested: each size holds the smaller ones) and D16 on the same frames under its 32 "
       "elements, both until validation stops improving; a third "
       "model trains D16 for exactly the optimiser steps no augmentation needed (equal "
       "compute), to show how much of the gain is data and how much is compute. Test CC / RE, "
       "noise-free.\n\n| training frames | none | d16 | d16, none's steps |\n|---|---|---|---|\n";
  for (int n : sizes_of(points))
    o << fmt::format("| {} | {} | {} | {} |\n", n, cell(find(points, "none", "converged", n)),
                     cell(find(points, "d16", "converged", n)),
                     cell(find(points, "d16", "equal_steps", n)));
  o << "\n![Test CC against training-set size](data_efficiency.png)\n"
    << "![Test RE against training-set size](data_efficiency_re.png)\n";
}

bool draw_efficiency_figures(const std::vector<EfficiencyPoint>& points,
                             const std::string& folder) {
  const std::filesystem::path dir(folder);
  const bool cc = draw_metric(points, true, (dir / "data_efficiency.png").string());
  return draw_metric(points, false, (dir / "data_efficiency_re.png").string()) && cc;
}

}  // namespace eitbench
