#include "eitbench/bench/report/press_pick.h"

#include <cmath>

namespace eitbench {

PressPick pick_without_labels(const std::vector<MeasuredRow>& rows) {
  PressPick p;
  bool any_real = false;
  for (const MeasuredRow& m : rows) {
    if (std::isnan(m.like_sensor_fraction_of_radius)) continue;
    if (!std::isnan(m.misfit_over_noise)) p.misfit_over_noise = m.misfit_over_noise;
    any_real |= m.tuned_on_real_frames;
  }
  p.real_frames_only = any_real && p.misfit_over_noise > kModelErrorRatio;
  for (const MeasuredRow& m : rows) {
    if (std::isnan(m.like_sensor_fraction_of_radius)) continue;
    if (p.real_frames_only && !m.tuned_on_real_frames) continue;
    if (!p.pick || m.like_sensor_fraction_of_radius < p.pick->like_sensor_fraction_of_radius)
      p.pick = &m;
  }
  return p;
}

}  // namespace eitbench
