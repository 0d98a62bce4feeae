#pragma once
// A learned reconstructor for the tank (docs/ktc.md#a-learned-reconstructor): eitbench's network
// from a difference frame (every value, a level's missing ones as 0) to the signed classes on a
// grid (+1 conductive, -1 resistive, 0 water), trained on simulated tanks, each at a random level,
// with or without the tank's symmetry group.
#include <cstdint>
#include <string>

#include "eitbench/augment/augmented_set.h"
#include "eitbench/bench/ktc/tank_simulation.h"
#include "eitbench/learned/learned_model.h"
#include "eitbench/learned/network_options.h"
#include "eitbench/learned/trainer.h"

namespace eitbench {

struct KtcNetworkOptions {
  bool group = true;       // every training tank under the tank's 8 elements as well
  long long steps = 6000;  // optimiser steps; the model kept is the best on validation
  int batch_size = 64;
  double learning_rate = 3e-3;          // the cosine schedule's peak
  long long validate_every = 64 * 200;  // training samples between validations
  int patience = 0;            // validations without improvement before early stopping; 0: never
  std::string device = "cpu";  // auto | cpu | cuda (TrainingOptions::device)
  double threshold = 0.5;      // an output at or beyond +-threshold is that class
  ModelSize size = ModelSize::small;
  std::uint64_t seed = 1;

  // InputError("KtcNetworkOptions", field) for a value out of range.
  void validate() const;
};

// `tanks` each expanded by the group when asked (pattern_action and the labels moved), then each
// row at a level drawn from 1 ... 7 (seeded), its missing values NaN; labels the signed classes.
LabelledFrames ktc_level_frames(const KtcSimulatedSet& tanks, const CurrentPatterns& patterns,
                                bool group, std::uint64_t seed);
// The same as the network learns them: the missing values 0.
LabelledFrames ktc_network_frames(const KtcSimulatedSet& tanks, const CurrentPatterns& patterns,
                                  bool group, std::uint64_t seed);

// What train_ktc_network trains with: the network for `inputs` values and labels on grid x grid,
// the optimiser's options, and the set-up the trainer checks frames against (the tank's protocol,
// no group: the set is expanded beforehand, current patterns moving linearly).
NetworkOptions ktc_network_options(const KtcNetworkOptions& options, int inputs, int grid);
TrainingOptions ktc_training_options(const KtcNetworkOptions& options);
AugmentSetup ktc_network_setup(const CurrentPatterns& patterns, int grid);

// Trains on `train`, keeps the best model on `validation` (both simulated, labels on one grid).
LearnedModel train_ktc_network(const KtcSimulatedSet& train, const KtcSimulatedSet& validation,
                               const CurrentPatterns& patterns, const KtcNetworkOptions& options);

// The classes on KTC's 256 x 256 grid of a change (a frame minus the empty tank's; NaN where a
// level removed the value).
ClassImage ktc_network_classes(const LearnedModel& model, const Eigen::VectorXd& change,
                               double threshold);
// The classes of a network's output image (n x n, the signed classes' scale): at or beyond
// +-threshold that class, each of KTC's pixels taking the output pixel under it.
ClassImage ktc_output_classes(const Eigen::VectorXd& output, double threshold);

}  // namespace eitbench
