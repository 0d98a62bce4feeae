// Stage 5: data efficiency, the paper's protocol (its Fig. 8). At each training-set size n, no
// augmentation trains on n frames drawn from the training split (labelled_frames: nested, by the
// run's seed) and D16 on the same n frames under the 32 elements of
// the group, both to convergence (early stopping; the main runs' step budget as the bound), so D16
// sees its 32-fold set. A third model, D16 with exactly the optimiser steps no augmentation needed
// at that n, separates what the data give from what the extra compute gives. At the whole
// training set the converged models are the main runs', and those are reused.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "eitbench/bench/data/training_data.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/bench/methods/training_run.h"
#include "stages.h"

namespace eitbench::run {
namespace fs = std::filesystem;
namespace {

// How a size's frames are chosen (labelled_frames), in each point's provenance.
constexpr const char* kSubsetRule = "n drawn from the training split by the seed, nested";

void copy_training(const TrainingSummary& t, long long samples_per_epoch, EfficiencyPoint& p) {
  p.steps = t.steps;
  p.samples_seen = t.samples;
  p.epochs = static_cast<int>((t.samples + samples_per_epoch - 1) / samples_per_epoch);
  p.converged = t.converged;
  p.best_epoch = t.best_epoch;
  p.training_samples_per_second = t.samples_per_second;
  p.fraction_of_gemm_peak = t.fraction_of_gemm_peak;
}

// The main run's figures for p, when p is a converged model on the whole training set.
bool from_main_run(const RunResults& main_runs, EfficiencyPoint& p) {
  for (const auto& row : main_runs.rows)
    if (row.method == "dnn" && row.augment == p.augment && std::isinf(row.snr_db))
      for (const auto& t : main_runs.training)
        if (t.augment == p.augment) {
          copy_training(t, p.train_size, p);
          p.test_mse = row.mse, p.cc = row.cc, p.re = row.re;
          p.cc_std = row.cc_std, p.re_std = row.re_std, p.frames = row.frames;
          return true;
        }
  return false;
}

std::string sweep_model_path(const Context& context, const std::string& name) {
  return (context.out / "models" / (name + ".pt")).string();
}

// Trains one sweep model on the first p.train_size training frames for `steps` optimiser steps
// and scores it, noise-free: when p.budget is "converged" with early stopping and the budget
// rule's doublings, as the main models train; "equal_steps" exactly those steps.
void train_point(const Context& context, const LearnedSetup& setup, const RunData& data,
                 const Reconstruction& reconstruction, long long steps, const std::string& name,
                 EfficiencyPoint& p) {
  TrainingOptions o = setup.training;
  o.augment = parse_group(p.augment, "augment");
  o.epochs = 0;
  o.steps = steps;
  if (p.budget == "equal_steps") o.patience = 0;  // exactly those steps (the best round kept)
  TrainingRun run;
  run.label = fmt::format("sweep {} {} n={}", p.augment, p.budget, p.train_size);
  run.out = sweep_model_path(context, name);
  Provenance provenance = training_provenance(context.config, data);
  provenance["point"] = name, provenance["steps"] = std::to_string(steps);
  provenance["subset"] = kSubsetRule;
  // No Keep here: train_point never reuses a finished model (run_sweep reuses its figures,
  // through the stage record), only a checkpoint or the stages of one killed.
  run.resume = context.cache.claim_model(run.label, run.out, provenance) && resumable(run.out);
  run.quiet = context.config.quiet;
  run.curves = false;
  // The converged arms follow the main models' rule; equal steps is exactly none's steps.
  if (p.budget == "converged") run.rule = context.config.budget_rule;
  TrainingResult r =
      train_and_save(setup.network, o,
                     labelled_frames(data.source, Split::train, p.train_size, context.config.seed),
                     labelled_frames(data.source, Split::validation), sensor_of(data.source), run);
  copy_training(training_summary(r.model, run.out, setup), p.train_size, p);
  const auto method = make_learned_reconstructor(r.model);
  const ResultRow row =
      evaluate_row(*method, data.test.frames, data.test.labels, reconstruction.grid, 0);
  p.test_mse = row.mse, p.cc = row.cc, p.re = row.re;
  p.cc_std = row.cc_std, p.re_std = row.re_std, p.frames = row.frames;
  context.say(fmt::format("data efficiency: {} {}, n={}: {} steps{}, test CC {:.3f}, RE {:.3f}",
                          p.augment, p.budget, p.train_size, p.steps,
                          p.converged ? " (converged)" : "", p.cc, p.re));
}

}  // namespace

std::vector<int> sweep_sizes(const std::vector<int>& sizes, int train_count) {
  std::vector<int> out;
  for (int n : sizes) {
    const int size = std::min(n, train_count);
    if (std::find(out.begin(), out.end(), size) == out.end()) out.push_back(size);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<EfficiencyPoint> run_sweep(const Context& context, const LearnedSetup& setup,
                                       const RunData& data, const Reconstruction& reconstruction,
                                       const RunResults& main_runs, const std::vector<int>& sizes) {
  std::vector<EfficiencyPoint> points;
  if (!data.labelled) return points;
  const RunConfig& config = context.config;
  const int train_count = static_cast<int>(data.source.indices(Split::train).size());
  const long long main_steps = config.epochs * steps_per_epoch(train_count, config.batch);
  auto point = [&](const std::string& augment, const std::string& budget, int n, long long steps) {
    EfficiencyPoint p;
    p.augment = augment, p.budget = budget, p.train_size = n;
    if (n == train_count && budget == "converged" && from_main_run(main_runs, p)) return p;
    const std::string name = fmt::format("efficiency_{}_{}_{}", augment, budget, n);
    Provenance provenance = data.provenance;  // the test frames it is scored on, too
    // The sensor file sets the model-based methods' model and the press fit, not the network's.
    provenance.erase("sensor");
    for (const auto& [key, value] : training_provenance(config, data)) provenance[key] = value;
    provenance["steps"] = std::to_string(steps);
    // Points made when a size took the split's first n frames are made again.
    provenance["subset"] = kSubsetRule;
    const std::string model = sweep_model_path(context, name);
    if (!context.cache.find(
            name, provenance, [&](const nlohmann::json& j) { p = efficiency_point_from_json(j); },
            kept_under_earlier_edge(config, provenance, model, setup.training))) {
      train_point(context, setup, data, reconstruction, steps, name, p);
      context.cache.save(name, provenance, to_json(p));
    }
    return p;
  };
  for (int n : sweep_sizes(sizes, train_count)) {
    const EfficiencyPoint none = point("none", "converged", n, main_steps);
    points.push_back(none);
    points.push_back(point("d16", "converged", n, main_steps));
    points.push_back(point("d16", "equal_steps", n, std::max(1LL, none.steps)));
  }
  return points;
}

}  // namespace eitbench::run
