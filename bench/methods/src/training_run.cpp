#include "eitbench/bench/methods/training_run.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/methods/model_file.h"
#include "eitbench/bench/report/loss_curves.h"
#include "eitbench/bench/support/progress.h"
#include "eitbench/bench/support/timing.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

std::string checkpoint_path(const std::string& model_path) {
  return model_path + ".checkpoint";
}

bool decided_as_now(const LearnedModel& model, const TrainingOptions& options) {
  try {
    const nlohmann::json t = nlohmann::json::parse(model.info().training);
    if (t.at("end").get<std::string>() != to_string(TrainingEnd::early_stopping)) return true;
    const auto history = history_from_json(t.at("history").dump(), "model");
    if (history.empty() || t.at("doublings").get<int>() != 0) return false;
    const LearningRateSchedule first_stage(options.learning_rate,
                                           t.at("budget_steps").get<long long>(), options.schedule);
    return stopped_with_rate_left(first_stage, history.back().steps);
  } catch (const nlohmann::json::exception&) {
  } catch (const InputError&) {
  }
  return false;
}

std::string loss_curve_path(const std::string& model_path, const std::string& extension) {
  const std::filesystem::path p(model_path);
  return (p.parent_path() / (p.stem().string() + "_loss." + extension)).string();
}

namespace {

std::string stage_path(const std::string& out) {
  return out + ".stage";
}

}  // namespace

bool resumable(const std::string& model_path) {
  return std::filesystem::exists(checkpoint_path(model_path)) ||
         (std::filesystem::exists(stage_path(model_path)) &&
          std::filesystem::exists(stage_path(model_path) + ".json"));
}

void remove_training_files(const std::string& model_path) {
  std::filesystem::remove(checkpoint_path(model_path));
  std::filesystem::remove(stage_path(model_path));
  std::filesystem::remove(stage_path(model_path) + ".json");
}

namespace {

// What the stages so far left: the best model, its stage's record, the merged history.
struct Stages {
  int done = 0;              // stages finished
  long long budget = 0;      // the budget in steps at the last stage's end
  std::vector<double> best;  // the best validation loss over the stages so far, after each
  std::vector<TrainingRecord> history;
  int best_round = 0, best_epoch = 0;  // in the merged history
  std::optional<LearnedModel> model;   // the best so far
};

void save_stages(const std::string& out, const Stages& st) {
  write_model_file(stage_path(out), *st.model);
  const nlohmann::json j{{"done", st.done},
                         {"budget", st.budget},
                         {"best", st.best},
                         {"history", nlohmann::json::parse(history_to_json(st.history))},
                         {"best_round", st.best_round},
                         {"best_epoch", st.best_epoch}};
  write_text_atomically(stage_path(out) + ".json", [&](std::ostream& o) { o << j.dump() << '\n'; });
}

// The stages a killed run finished (none when there is no record), InputError naming the file
// when it is not one of this eitbench's.
Stages load_stages(const std::string& out) {
  Stages st;
  const std::string path = stage_path(out) + ".json";
  if (!std::filesystem::exists(path) || !std::filesystem::exists(stage_path(out))) return st;
  try {
    const nlohmann::json j = nlohmann::json::parse(read_file_bytes(path));
    st.done = j.at("done").get<int>();
    st.budget = j.at("budget").get<long long>();
    st.best = j.at("best").get<std::vector<double>>();
    st.history = history_from_json(j.at("history").dump(), path);
    st.best_round = j.at("best_round").get<int>();
    st.best_epoch = j.at("best_epoch").get<int>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, "", std::string("not this eitbench's stage record: ") + e.what());
  }
  st.model = read_model_file(stage_path(out));
  return st;
}

// The rounds of one stage until its trainer is done, a checkpoint after each.
void run_stage(Trainer& trainer, const TrainingRun& run, const std::string& checkpoint,
               const std::string& label, bool resumed) {
  const long long total = trainer.total_steps();
  const long long done_before = trainer.history().empty() ? 0 : trainer.history().back().steps;
  Progress progress(label, static_cast<int>(total), run.quiet);
  if (resumed)
    progress.note(fmt::format("{}: resuming after round {} ({} of at most {} steps)", label,
                              trainer.history().size(), done_before, total));
  long long steps = done_before;
  while (!trainer.done()) {
    double loss_sum = 0;
    long long count = 0, round_steps = 0;
    const TrainingRecord r = trainer.run_round([&](long long step, long long, double loss) {
      loss_sum += loss * double(step - round_steps), count += step - round_steps;
      steps += step - round_steps, round_steps = step;
      const long long epoch = (steps + trainer.steps_per_epoch() - 1) / trainer.steps_per_epoch();
      progress.update(static_cast<int>(steps),
                      fmt::format("epoch {}, loss {:.4g}", epoch, loss_sum / count));
    });
    write_bytes_atomically(checkpoint, trainer.checkpoint());
    progress.note(fmt::format(
        "{} round {:3d} (epoch {}, {} steps): train {:.5g}, validation {:.5g}{}, lr {:.3g}, "
        "{:.0f} samples/s",
        label, r.round, r.epoch, r.steps, r.train_loss, r.validation_loss,
        trainer.best_round() == r.round ? " (best)" : "", r.learning_rate, r.samples_per_second));
  }
  if (trainer.converged())
    progress.note(fmt::format("{}: stopped early, no improvement in {} rounds; best round {}",
                              label, trainer.options().patience, trainer.best_round()));
}

// Early stopping ended the stage with rate left (budget_rule.h): the model stopped improving
// while the rate could still move it, so the budget was not what ended it. (Stopped near or at
// the floor, the schedule may have ended it: only a doubling can tell.)
bool ended_with_rate_left(const Trainer& trainer) {
  return trainer.converged() && !trainer.history().empty() &&
         stopped_with_rate_left(trainer.schedule(), trainer.history().back().steps);
}

// A finished stage joined to the ones before: its rounds after theirs, its model if better.
void add_stage(Stages& st, const Trainer& trainer) {
  const TrainingRecord last = st.history.empty() ? TrainingRecord{} : st.history.back();
  double stage_best = INFINITY;
  for (TrainingRecord r : trainer.history()) {
    stage_best = std::min(stage_best, r.validation_loss);
    r.round += last.round, r.epoch += last.epoch, r.steps += last.steps, r.samples += last.samples;
    st.history.push_back(r);
  }
  const double before = st.best.empty() ? INFINITY : st.best.back();
  if (!st.model || stage_best < before) {
    st.model = trainer.best_model();
    st.best_round = last.round + trainer.best_round();
    st.best_epoch = last.epoch + trainer.best_epoch();
  }
  st.best.push_back(std::min(stage_best, before));
  st.budget = st.done == 0 ? trainer.total_steps() : 2 * st.budget;
  ++st.done;
}

// The final model's training record: the best stage's, with the merged history and the rule's end.
void record_training(LearnedModel& model, const Stages& st, const BudgetRule& rule,
                     TrainingEnd end) {
  nlohmann::json t = nlohmann::json::parse(model.info().training);
  t["history"] = nlohmann::json::parse(history_to_json(st.history));
  t["best_round"] = st.best_round;
  t["best_epoch"] = st.best_epoch;
  t["budget_steps"] = st.budget;
  t["steps"] = st.history.empty() ? 0 : st.history.back().steps;
  t["samples"] = st.history.empty() ? 0 : st.history.back().samples;
  t["rounds"] = st.history.size();
  t["converged"] = converged(end);
  t["end"] = to_string(end);
  t["doublings"] = st.done - 1;
  t["stage_best"] = st.best;
  t["rule"] = {{"max_doublings", rule.max_doublings}, {"tolerance", rule.tolerance}};
  model.info().training = t.dump();
}

}  // namespace

TrainingResult train_and_save(const NetworkOptions& network, const TrainingOptions& options,
                              LabelledFrames train, const LabelledFrames& validation,
                              const AugmentSetup& sensor, const TrainingRun& run) {
  run.rule.validate();
  const std::string checkpoint = checkpoint_path(run.out);
  temporary_path_for(run.out);  // the output folder must exist before hours of training
  if (run.resume && !resumable(run.out))
    throw InputError("--resume", "",
                     "no checkpoint at " + checkpoint +
                         ": nothing to resume (run without "
                         "--resume to start)");
  // A fresh training leaves nothing of an earlier one's stages: killed in its first stage, its
  // --resume would otherwise join its checkpoint to their record.
  if (!run.resume) remove_training_files(run.out);
  Stages st = run.resume ? load_stages(run.out) : Stages{};
  bool resumed = st.done > 0;
  const bool more = run.rule.max_doublings > 0;  // stages after this one may follow
  TrainingEnd end = TrainingEnd::budget;
  long long steps_per_epoch_seen = 0, samples_per_epoch_seen = 0;  // the data's, every stage
  const auto t0 = std::chrono::steady_clock::now();
  while (true) {
    const std::string label =
        st.done == 0 ? run.label : fmt::format("{} (doubling {})", run.label, st.done);
    std::unique_ptr<Trainer> trainer;
    const bool from_checkpoint = run.resume && std::filesystem::exists(checkpoint);
    LabelledFrames data = more ? train : std::move(train);
    if (from_checkpoint) {
      trainer = Trainer::resume(read_file_bytes(checkpoint), checkpoint, std::move(data),
                                validation, sensor);
      resumed = true;
    } else {
      TrainingOptions o = options;
      if (st.done > 0) {  // as many steps again, a fresh schedule run down to its floor
        o.epochs = 0, o.steps = st.budget;
        o.patience_after_decay = true;
      }
      trainer = std::make_unique<Trainer>(network, o, std::move(data), validation, sensor);
      if (st.done > 0) trainer->start_from(*st.model, stage_path(run.out));
    }
    run_stage(*trainer, run, checkpoint, label, from_checkpoint);
    add_stage(st, *trainer);
    steps_per_epoch_seen = trainer->steps_per_epoch();
    samples_per_epoch_seen = trainer->samples_per_epoch();
    std::filesystem::remove(checkpoint);
    if (!more) {
      end = !trainer->converged()            ? TrainingEnd::budget
            : ended_with_rate_left(*trainer) ? TrainingEnd::early_stopping
                                             : TrainingEnd::floor;
      break;
    }
    if (st.done == 1 && ended_with_rate_left(*trainer)) {
      end = TrainingEnd::early_stopping;  // the budget sufficed: no doubling can tell more
      break;
    }
    const int doublings = st.done - 1;
    const double previous = st.done >= 2 ? st.best[st.best.size() - 2] : INFINITY;
    if (doublings > 0 && !double_again(run.rule, previous, st.best.back(), doublings)) {
      end =
          doubling_paid(run.rule, previous, st.best.back()) ? TrainingEnd::cap : TrainingEnd::rule;
      break;
    }
    save_stages(run.out, st);
    if (!run.quiet)
      fmt::print(stderr, "{}: budget doubled to {} steps (best validation {:.5g})\n", run.label,
                 2 * st.budget, st.best.back());
  }
  record_training(*st.model, st, run.rule, end);
  TrainingResult result{std::move(*st.model),
                        st.history,
                        st.best_round,
                        st.best_epoch,
                        converged(end),
                        end,
                        st.done - 1,
                        st.best,
                        st.budget,
                        steps_per_epoch_seen,
                        samples_per_epoch_seen,
                        seconds_since(t0),
                        resumed};
  write_model_file(run.out, result.model);
  if (run.curves)
    write_loss_curves(loss_curve_path(run.out, "csv"), loss_curve_path(run.out, "png"),
                      {{to_string(options.augment), result.history}});
  std::filesystem::remove(stage_path(run.out));
  std::filesystem::remove(stage_path(run.out) + ".json");
  return result;
}

}  // namespace eitbench
