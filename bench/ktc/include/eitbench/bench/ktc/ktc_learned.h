#pragma once
// The learned rows of a KTC run (docs/ktc.md#the-learned-models): eitbench's network trained on
// simulated tanks like the challenge's (the calibrated tank, the targets' contrasts in a band that
// holds those measured on the training samples, the frames' measured noise), without and with the
// tank's symmetry group, then scored on the training samples at every level as the model-based
// methods are. Nothing of the network is tuned on the samples: its segmentation threshold is
// fixed beforehand.
#include <string>
#include <vector>

#include "eitbench/bench/ktc/ktc_method.h"
#include "eitbench/bench/ktc/tank_network.h"
#include "eitbench/bench/ktc/tank_post_processing.h"
#include "eitbench/bench/ktc/tank_simulation.h"
#include "eitbench/bench/methods/budget_rule.h"

namespace eitbench {

// The memory a KTC run's learned rows may take (the machine this is sized for has 24 GiB).
constexpr double kKtcLearnedMemoryBudget = 12.0 * (1 << 30);

struct KtcLearnedOptions {
  // The models trained: "none" (the simulated tanks as drawn) and "group" (each also under the
  // tank's 8 symmetry elements). Empty: no learned rows.
  std::vector<std::string> arms{"none", "group"};
  // The networks trained for each arm: "dnn" reads the frame (tank_network.h), "dnn-post" a
  // one-step image of it (tank_post_processing.h), as the challenge's winners did.
  std::vector<std::string> networks{"dnn", "dnn-post"};
  KtcOneStep one_step;     // dnn-post's image
  int one_step_grid = 64;  // that image's pixels a side (the run's --pixels), for the estimate
  int tanks = 4000;        // simulated: 80 % to train on, 10 % to validate, 10 % to test
  // Each target's conductivity ratio to the water, drawn log-uniformly in a band fixed
  // beforehand: plastic 10-100 times below the water, metal 10-100 times above. The contrasts
  // fitted to the samples are a check of the band (the residual inside it), not an input:
  // nothing of the samples enters the training data.
  double resistive_low = 0.01, resistive_high = 0.1;
  double conductive_low = 10, conductive_high = 100;
  int grid = 64;  // the labels' pixels across the tank's square
  // steps: the budget before the rule's doublings; group: set per arm. Early stopping after 6
  // validations (1,200 steps) without a gain.
  KtcNetworkOptions network = [] {
    KtcNetworkOptions n;
    n.patience = 6;
    return n;
  }();
  // Up to four doublings while the last lowered validation by > 1 %: with three, the group model
  // ended at the cap at two seeds (docs/ktc.md#the-learned-models).
  BudgetRule rule{4, 0.01};

  // InputError naming the flag (--augment, --ktc-learned, --ktc-tanks, --ktc-steps) or the
  // options' field;
  // --ktc-tanks when the training frames (with the group, 8 a tank), their labels and the
  // trainer's copies would pass kKtcLearnedMemoryBudget.
  void validate() const;
  double training_bytes() const;                  // the estimate checked against the budget
  bool trains(const std::string& network) const;  // whether `networks` names it
};

// One learned model's row.
struct KtcLearnedArm {
  std::string network = "dnn";  // dnn | dnn-post
  std::string arm;              // none | group
  std::string model_file;       // in the run's folder: ktc_<network>_<arm>.model
  long long training_frames = 0;
  TrainingEnd end = TrainingEnd::budget;
  long long steps = 0;  // the budget at the end (doubled each stage)
  int doublings = 0;
  std::vector<double> stage_best;  // the best validation MSE after each stage
  double training_seconds = 0;
  // On the simulated test split, each tank at a level drawn as in training: the correlation of
  // the output with the signed classes (mean over tanks) and the KTC score (mean).
  double test_cc = 0, test_score = 0;
  std::vector<std::vector<double>> scores;       // [level][sample] on the real samples
  std::vector<std::vector<ClassImage>> classes;  // [level][sample], for the figures
  double median_ms = 0;                          // per frame, on this machine's CPU
};

struct KtcLearnedResults {
  KtcLearnedOptions options;
  // Fitted to the samples, and without each one: the band's check. A target's effect on the
  // frame saturates far from the water's conductivity, so the fits scatter; what tells whether
  // the band is like the samples is the best residual inside it against the best anywhere.
  KtcContrastFits contrasts;
  KtcContrasts in_band;  // the best fit inside the band
  double noise = 0;      // V a value, from the reference's repeated patterns
  double simulation_seconds = 0;
  int train = 0, validation = 0, test = 0;  // simulated tanks in each split
  std::vector<KtcLearnedArm> arms;
};

// The simulated tanks the learned rows train, validate and test on: `options.tanks` of them drawn
// with the network's seed on the calibrated tank, each target's contrast in the options' band,
// each value with the noise its reference's repeated patterns measure (V).
KtcSimulationOptions ktc_training_simulation(const KtcLearnedOptions& options, const KtcTank& tank);

// Simulates, trains every network and arm into <out>/ktc_<network>_<arm>.model (with its loss
// curves) and scores it on `samples` at `levels`. `contrasts` is the contrast fit to the samples'
// level-1 changes and truths (fit_ktc_contrasts_held_out), which the run has made already for the
// model misfits. The model files record the protocol (the patterns), the tank, the contrasts, the
// level handling and the threshold.
KtcLearnedResults run_ktc_learned(const KtcSetup& setup, const std::vector<KtcMeasurement>& samples,
                                  const std::vector<ClassImage>& truths,
                                  const KtcContrastFits& contrasts, const std::vector<int>& levels,
                                  const KtcLearnedOptions& options, const std::string& out,
                                  bool quiet);

// The model file of a network and arm in a run's folder.
std::string ktc_model_path(const std::string& run, const std::string& network,
                           const std::string& arm);

// A trained model's KTC record (its training JSON's "ktc" block): the threshold it segments at.
// InputError(source, "ktc") for a model that is not a KTC run's.
double ktc_model_threshold(const LearnedModel& model, const std::string& source);
// A dnn-post model's one-step method, from its KTC record. InputError(source, "ktc.one_step") for
// a model without one; "ktc.one_step.pixels" when its images are not `pixels` a side (the run's
// grid).
KtcOneStep ktc_model_one_step(const LearnedModel& model, const std::string& source, int pixels);

}  // namespace eitbench
