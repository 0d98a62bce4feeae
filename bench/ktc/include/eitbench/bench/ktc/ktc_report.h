#pragma once
// A KTC run's records (docs/ktc.md#the-benchmark): results.json (the tank, every method's scores
// and settings), report.md (the score table per method and level, against the challenge's
// published totals) and the figures (segmentations beside the truths), in the run's folder; and
// the settings `eitbench ktc --from RUN` reads back.
#include <map>
#include <string>

#include "eitbench/bench/ktc/ktc_run.h"

namespace eitbench {

// Writes results.json, report.md and (where this build draws) ktc_level<L>.png into options.out,
// each whole or not at all.
void write_ktc_run(const KtcRunResults& results);

// What a run tuned, for `eitbench ktc --from RUN`.
struct KtcRunSettings {
  std::string path;       // RUN/results.json
  KtcTankOptions tank;    // the geometry the run calibrated
  double background = 0;  // its calibration
  Eigen::VectorXd contact_impedances;
  std::string reference_hash;  // of the ref.mat it calibrated to
  KtcNoise noise;              // the run's; each method's relative part is its own (Method)
  int grid = 64;
  struct Method {
    double lambda = 0;
    double noise_relative = 0;  // KtcNoise::relative tuned for it (with noise.floor)
    SegmentationRule rule;
  };
  std::map<std::string, Method> methods;  // tuned on every sample
  // Tuned on the run's simulated tanks (--tuning-tanks), for the methods it so tuned.
  std::map<std::string, Method> simulation_tuned;
  // Tuned on every sample and those tanks together, for the same methods.
  std::map<std::string, Method> joint_tuned;
  // learned network and arm ("dnn none", "dnn-post group", ...) -> its model file
  std::map<std::string, std::string> models;
};

// Reads RUN/results.json of a KTC run. InputError naming the file and the field when it is no
// KTC run's, or a field is missing or of the wrong type.
KtcRunSettings read_ktc_settings(const std::string& run);

}  // namespace eitbench
