// Touch metrics over frames: the summary of the per-frame matches.
#include <algorithm>
#include <cmath>
#include <map>

#include "eitbench/bench/methods/touch_metrics.h"
#include "eitbench/bench/methods/touch_signal.h"
#include "eitbench/jacobian/error.h"
#include "order_statistics.h"

namespace eitbench {
namespace {

using detail::quantile;

std::vector<double> sorted_errors(const std::vector<FrameMatch>& frames,
                                  std::vector<double> FrameMatch::*errors) {
  std::vector<double> all;
  for (const auto& f : frames) all.insert(all.end(), (f.*errors).begin(), (f.*errors).end());
  std::sort(all.begin(), all.end());
  return all;
}

double count_accuracy(const std::vector<FrameMatch>& frames) {
  const auto right = std::count_if(frames.begin(), frames.end(),
                                   [](const FrameMatch& f) { return f.count_correct(); });
  return static_cast<double>(right) / static_cast<double>(frames.size());
}

// Count accuracy and centre median of the frames with each true number of touches.
std::vector<TouchCountScores> by_true_count(const std::vector<FrameMatch>& frames) {
  std::map<int, std::vector<FrameMatch>> groups;
  for (const auto& f : frames) groups[f.truth].push_back(f);
  std::vector<TouchCountScores> out;
  for (const auto& [touches, group] : groups)
    out.push_back({touches, static_cast<int>(group.size()), count_accuracy(group),
                   quantile(sorted_errors(group, &FrameMatch::centre_errors), 0.5)});
  return out;
}

// Every true touch's signal: one for each, none NaN.
bool signals_known(const std::vector<FrameMatch>& frames) {
  for (const auto& f : frames) {
    if (static_cast<int>(f.truth_signals.size()) != f.truth) return false;
    for (double s : f.truth_signals)
      if (!std::isfinite(s)) return false;
  }
  return true;
}

// Count accuracy on the frames whose every touch is visible, and the touches found by signal.
void by_signal(const std::vector<FrameMatch>& frames, TouchScores& s) {
  std::vector<FrameMatch> visible;
  for (const auto& f : frames)
    if (std::all_of(f.truth_signals.begin(), f.truth_signals.end(),
                    [](double v) { return v >= kVisibleSignal; }))
      visible.push_back(f);
  s.visible_frames = static_cast<int>(visible.size());
  if (!visible.empty()) s.visible_count_accuracy = count_accuracy(visible);
  double from = 0;
  for (std::size_t b = 0; b <= kSignalBinEdges.size(); ++b) {
    TouchSignalScores bin;
    bin.from = from, bin.to = b < kSignalBinEdges.size() ? kSignalBinEdges[b] : INFINITY;
    from = bin.to;
    for (const auto& f : frames) {
      std::vector<bool> found(f.truth_signals.size(), false);
      for (const auto& [t, unused] : f.pairs) found[static_cast<std::size_t>(t)] = true;
      for (std::size_t t = 0; t < f.truth_signals.size(); ++t)
        if (f.truth_signals[t] >= bin.from && f.truth_signals[t] < bin.to)
          ++bin.touches, bin.found += found[t];
    }
    s.by_signal.push_back(bin);
  }
}

}  // namespace

TouchScores summarize_touches(const std::vector<FrameMatch>& frames) {
  TouchScores s;
  if (frames.empty()) return s;
  s.frames = static_cast<int>(frames.size());
  s.count_accuracy = count_accuracy(frames);
  const std::vector<double> centre = sorted_errors(frames, &FrameMatch::centre_errors);
  s.centre_error_median = quantile(centre, 0.5);
  s.centre_error_p90 = quantile(centre, 0.9);
  s.radius_error_median = quantile(sorted_errors(frames, &FrameMatch::radius_errors), 0.5);
  if (!centre.empty())
    for (int k = 0; k <= 20; ++k) s.centre_error_quantiles.push_back(quantile(centre, k / 20.0));
  double missed = 0, phantom = 0;
  for (const auto& f : frames) {
    missed += f.missed(), phantom += f.phantom();
    s.true_touches += f.truth;
    s.matched += static_cast<int>(f.pairs.size());
  }
  s.missed_per_frame = missed / s.frames;
  s.phantom_per_frame = phantom / s.frames;
  s.by_count = by_true_count(frames);
  if (signals_known(frames)) by_signal(frames, s);
  return s;
}

TouchScores score_touches(const TouchFrames& found, const TouchFrames& truth, double radius,
                          const TouchOptions& options) {
  if (found.size() != truth.size())
    throw InputError("score_touches", "found", "must hold one list a frame of the truth");
  std::vector<FrameMatch> frames;
  for (std::size_t i = 0; i < found.size(); ++i)
    frames.push_back(match_touches(found[i], truth[i], radius, options));
  return summarize_touches(frames);
}

}  // namespace eitbench
