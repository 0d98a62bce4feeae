#pragma once
// What a benchmark run does: the data, the methods, the budgets. A preset fills every field;
// `eitbench run`'s flags then change some.
#include <cstdint>
#include <string>
#include <vector>

#include "eitbench/bench/data/simulate.h"
#include "eitbench/bench/methods/budget_rule.h"
#include "eitbench/jacobian/disk_mesh.h"
#include "eitbench/learned/schedule.h"

namespace eitbench {

struct RunConfig {
  std::string preset = "quick";  // tiny | quick | standard | paper: the data and the budgets
  std::string data;              // a data set (or measured frames) instead of simulating
  std::string reference;         // measured frames: the empty sensor's frame
  std::string sensor;  // a calibrated sensor file: the reconstruction model's impedances, sigma_0
  std::string out;     // the output folder
  // A sensor of another shape: a Gmsh mesh the preset's set is simulated on (docs/sensors.md).
  std::string mesh_file;
  std::uint64_t seed = 1;
  bool resume = false;  // reuse what an interrupted run in `out` finished
  bool quiet = false;
  int electrodes = 16;  // of measured frames (--data with --reference)
  // The measurement protocol the preset's set is simulated on (docs/protocols.md): adjacent,
  // adjacent-ascending, opposite, skip-K or a CSV file; magnitude: frames are |v|.
  std::string protocol = "adjacent";
  bool magnitude = false;
  // The simulated touches' sizes and domain randomisation (docs/real-presses.md): the presets'
  // draws by default.
  SimulationVariation variation;

  // Real presses (docs/real-presses.md): a press set to score every method on (`measured`) and a
  // labelled press set of the same sensor that tunes them (`press_calibration`); the preset is
  // simulated on the measured set's protocol.
  std::string measured, press_calibration;
  // Fine-tuning on the first n presses of press_calibration (-1: all of them), each size with and
  // without d16 augmentation, beside the same network trained on them from scratch; 0: the model
  // trained in simulation as it is. Empty: no fine-tuning.
  std::vector<int> finetune;
  // A training on presses: its budget in optimiser steps (early stopping on a fifth of the n
  // presses ends it sooner) and its validation interval in samples. A network trained on 80
  // hydrogel presses from scratch sat on blank images for its first 300 steps: validating every
  // 2,048 samples, early stopping ended it there; every 8,192, it went on to 5 mm mean error.
  long long finetune_steps = 2400, finetune_validate_every = 8192;
  double radius_mm = 0;  // the sensor's radius in millimetres, for the report (0: not given)

  std::vector<double> snrs;           // dB; infinity: noise-free
  std::vector<std::string> methods;   // model-based
  std::vector<std::string> augments;  // the learned reconstructor's
  bool augments_chosen = false;       // by the user: a sensor mesh then keeps them (if it can)
  MeshDensity mesh = MeshDensity::medium;
  MeshDensity simulation = MeshDensity::fine;
  std::string model = "small";
  std::string device = "cpu";
  int threads = 2;
  int epochs = 25, batch = 128;  // epochs: the training budget, an upper bound
  // The schedule's peak: 1e-2 trained the small model to a 5 % lower validation MSE than 3e-3 in
  // the same 300 epochs of D16 on the quick set (0.00440 against 0.00464).
  double learning_rate = 1e-2;
  std::string schedule = "cosine";
  // Where the cosine reaches its floor, as a fraction of the budget's steps (the rest is left for
  // early stopping to find the end): ScheduleOptions::decay_fraction, its default 0.6 too.
  double decay = ScheduleOptions().decay_fraction;
  long long validate_every = 16384;  // training samples between validations
  int patience = 5;                  // validations without improvement before stopping
  // Doublings of the budget after `epochs` (budget_rule.h): every learned model of the run and the
  // sweep's converged arms follow it.
  BudgetRule budget_rule;
  double min_improvement = 5e-3;      // relative: what counts as an improvement
  std::vector<int> efficiency_sizes;  // training-set sizes of the data-efficiency sweep
  int sweep_frames = 12;  // validation frames for the iterative methods' hyperparameter sweep
  int timed_frames = 32;  // test frames reconstructed one at a time for the latency figures
  // Validation frames each method reconstructs at each SNR to choose its touch threshold: TV and
  // GN take 50-90 ms a frame on 2 cores, so 40 frames x 4 SNRs add about 22 s to the quick run.
  int touch_validation_frames = 40;
  int figure_samples = 8;
  // This process's part of the run (docs/scaling.md): shard `shard_index` of `shard_count` makes
  // its share of the run's units of work (model-based methods, learned models, sweep sizes) in
  // <out>/shards/K-of-N/, for `eitbench merge` to join. 1: the whole run.
  int shard_index = 0, shard_count = 1;
  // The run's flags as given, without --shard, --out and --resume: a shard records them so that
  // merge makes the same run from the shards' stages.
  std::vector<std::string> arguments;
  // Make the run from the finished shards in <out>/shards/ (eitbench merge): gathered under the
  // folder's lock, refused unless made for this very run (its fingerprint); then every stage is
  // found made.
  bool merge_shards = false;

  // The preset's data and budgets; InputError naming --preset for an unknown one.
  static RunConfig for_preset(const std::string& preset);
};

}  // namespace eitbench
