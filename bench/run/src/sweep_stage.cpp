// Stage 5: data efficiency (the paper's Fig. 8): test scores against the training-set size, at
// equal optimiser steps and at equal epochs. By default both budgets are the main runs' (their
// epochs; their steps on the whole training set), so at the whole set the sweep's models are the
// main runs' models, and those are reused.
#include <fmt/core.h>

#include <cmath>

#include "eitbench/bench/data/training_data.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/bench/methods/training_run.h"
#include "stages.h"

namespace eitbench::run {
namespace fs = std::filesystem;
namespace {

// The steps and epochs of each budget.
struct SweepBudgets {
  long long main_steps = 0;  // the main runs' steps on the whole training set
  long long steps = 0;
  int epochs = 0;
};

SweepBudgets budgets(const RunConfig& config, int train_count) {
  const long long per_epoch =
      train_count / config.batch + (train_count % config.batch >= 2 ? 1 : 0);
  SweepBudgets b;
  b.main_steps = config.epochs * per_epoch;
  b.epochs = config.efficiency_epochs > 0 ? config.efficiency_epochs : config.epochs;
  b.steps = config.efficiency_steps > 0 ? config.efficiency_steps
                                        : config.epochs * std::max(1LL, per_epoch);
  return b;
}

// The main run's figures for p, when the sweep point is the main run (the whole set, its budget).
bool from_main_run(const RunResults& main_runs, EfficiencyPoint& p) {
  for (const auto& row : main_runs.rows)
    if (row.method == "dnn" && row.augment == p.augment && std::isinf(row.snr_db)) {
      for (const auto& t : main_runs.training)
        if (t.augment == p.augment)
          p.steps = t.steps, p.epochs = t.history.empty() ? 0 : t.history.back().epoch;
      p.test_mse = row.mse, p.cc = row.cc, p.re = row.re;
      return true;
    }
  return false;
}

// Trains one sweep model on the first p.train_size training samples and scores it (noise-free).
void train_point(const Context& context, const LearnedSetup& setup, const RunData& data,
                 const Reconstruction& reconstruction, const SweepBudgets& b,
                 const std::string& name, EfficiencyPoint& p) {
  TrainingOptions o = setup.training;
  o.augment = parse_group(p.augment, "augment");
  if (p.budget == "steps")
    o.steps = b.steps;
  else
    o.epochs = b.epochs;
  TrainingRun run;
  run.out = (context.out / "models" / (name + ".pt")).string();
  run.resume = context.config.resume && fs::exists(checkpoint_path(run.out));
  run.quiet = context.config.quiet;
  run.label = fmt::format("sweep {} {} n={}", p.augment, p.budget, p.train_size);
  run.curves = false;
  TrainingResult r =
      train_and_save(setup.network, o, labelled_frames(data.source, Split::train, p.train_size),
                     labelled_frames(data.source, Split::validation), sensor_of(data.source), run);
  const auto method = make_learned_reconstructor(r.model);
  const ResultRow row =
      evaluate_row(*method, data.test.frames, data.test.labels, reconstruction.grid, 0);
  p.steps = r.history.back().steps;
  p.epochs = r.history.back().epoch;
  p.test_mse = row.mse, p.cc = row.cc, p.re = row.re;
  context.say(
      fmt::format("data efficiency: {} at equal {}, n={}: {} steps, test MSE {:.4g}, CC {:.3f}",
                  p.augment, p.budget, p.train_size, p.steps, p.test_mse, p.cc));
}

}  // namespace

std::vector<EfficiencyPoint> run_sweep(const Context& context, const LearnedSetup& setup,
                                       const RunData& data, const Reconstruction& reconstruction,
                                       const RunResults& main_runs) {
  std::vector<EfficiencyPoint> points;
  if (!data.labelled) return points;
  const RunConfig& config = context.config;
  const int train_count = static_cast<int>(data.source.indices(Split::train).size());
  const SweepBudgets b = budgets(config, train_count);
  for (const std::string augment : {"none", "d16"})
    for (const std::string budget : {"steps", "epochs"})
      for (int n : config.efficiency_sizes) {
        if (n > train_count) continue;
        EfficiencyPoint p;
        p.augment = augment, p.budget = budget, p.train_size = n;
        const bool main_budget =
            budget == "steps" ? b.steps == b.main_steps : b.epochs == config.epochs;
        if (n == train_count && main_budget && from_main_run(main_runs, p)) {
          points.push_back(p);
          continue;
        }
        const std::string name = fmt::format("efficiency_{}_{}_{}", augment, budget, n);
        if (!context.cache.find(
                name, [&](const nlohmann::json& j) { p = efficiency_point_from_json(j); })) {
          train_point(context, setup, data, reconstruction, b, name, p);
          context.cache.save(name, to_json(p));
        }
        points.push_back(p);
      }
  return points;
}

}  // namespace eitbench::run
