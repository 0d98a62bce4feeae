#pragma once
// What the learned reconstructor's suites share: a tiny data set and a network small enough for
// tests.
#include "eitbench/bench/data/simulate.h"
#include "eitbench/bench/data/training_data.h"
#include "eitbench/learned.h"

namespace eitbench::testing {

// The tiny preset on the coarse mesh: 60 training samples, 14 validation, 7 test, in seconds.
inline const Dataset& tiny() {
  static const Dataset data = [] {
    SimulationOptions o;
    o.preset = "tiny";
    o.seed = 7;
    o.density = MeshDensity::coarse;
    return simulate_dataset(o);
  }();
  return data;
}

// A network small enough for tests: 104 -> 64 -> 8 x 8 x 8 -> 8, 4 -> 64 x 64 (pixel shuffle).
inline NetworkOptions test_network() {
  NetworkOptions n;
  n.hidden = {64};
  n.latent_channels = 8;
  n.decoder_channels = {8, 4};
  n.dropout = 0.1;
  return n;
}

// The tiny validation split with every label zero: training moves away from it, so validation
// loss grows from the first rounds on and early stopping ends a run early.
inline LabelledFrames zero_label_validation() {
  LabelledFrames validation = labelled_frames(tiny(), Split::validation);
  validation.circles.clear();
  validation.labels.setZero(validation.frames.rows(), 64 * 64);
  return validation;
}

}  // namespace eitbench::testing
