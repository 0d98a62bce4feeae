#include "eitbench/bench/methods/training_run.h"

#include <fmt/core.h>

#include <chrono>
#include <filesystem>

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

std::string loss_curve_path(const std::string& model_path, const std::string& extension) {
  const std::filesystem::path p(model_path);
  return (p.parent_path() / (p.stem().string() + "_loss." + extension)).string();
}

TrainingResult train_and_save(const NetworkOptions& network, const TrainingOptions& options,
                              LabelledFrames train, const LabelledFrames& validation,
                              const AugmentSetup& sensor, const TrainingRun& run) {
  const std::string checkpoint = checkpoint_path(run.out);
  temporary_path_for(run.out);  // the output folder must exist before hours of training
  std::unique_ptr<Trainer> trainer;
  bool resumed = false;
  if (run.resume) {
    if (!std::filesystem::exists(checkpoint))
      throw InputError("--resume", "",
                       "no checkpoint at " + checkpoint +
                           ": nothing to resume (run without "
                           "--resume to start)");
    trainer = Trainer::resume(read_file_bytes(checkpoint), checkpoint, std::move(train), validation,
                              sensor);
    resumed = true;
  } else {
    trainer = std::make_unique<Trainer>(network, options, std::move(train), validation, sensor);
  }
  const long long total = trainer->total_steps();
  const long long done_before = trainer->history().empty() ? 0 : trainer->history().back().steps;
  Progress progress(run.label, static_cast<int>(total), run.quiet);
  if (resumed)
    progress.note(fmt::format("{}: resuming after round {} ({} of at most {} steps)", run.label,
                              trainer->history().size(), done_before, total));
  const auto t0 = std::chrono::steady_clock::now();
  long long steps = done_before;
  while (!trainer->done()) {
    double loss_sum = 0;
    long long count = 0, round_steps = 0;
    const TrainingRecord r = trainer->run_round([&](long long step, long long, double loss) {
      loss_sum += loss * double(step - round_steps), count += step - round_steps;
      steps += step - round_steps, round_steps = step;
      const long long epoch = (steps + trainer->steps_per_epoch() - 1) / trainer->steps_per_epoch();
      progress.update(static_cast<int>(steps),
                      fmt::format("epoch {}, loss {:.4g}", epoch, loss_sum / count));
    });
    write_bytes_atomically(checkpoint, trainer->checkpoint());
    progress.note(fmt::format(
        "{} round {:3d} (epoch {}, {} steps): train {:.5g}, validation {:.5g}{}, lr {:.3g}, "
        "{:.0f} samples/s",
        run.label, r.round, r.epoch, r.steps, r.train_loss, r.validation_loss,
        trainer->best_round() == r.round ? " (best)" : "", r.learning_rate, r.samples_per_second));
  }
  if (trainer->converged())
    progress.note(fmt::format("{}: stopped early, no improvement in {} rounds; best round {}",
                              run.label, trainer->options().patience, trainer->best_round()));
  TrainingResult result{
      trainer->best_model(),      trainer->history(),
      trainer->best_round(),      trainer->best_epoch(),
      trainer->converged(),       trainer->total_steps(),
      trainer->steps_per_epoch(), trainer->samples_per_epoch(),
      seconds_since(t0),          resumed,
  };
  write_model_file(run.out, result.model);
  if (run.curves)
    write_loss_curves(loss_curve_path(run.out, "csv"), loss_curve_path(run.out, "png"),
                      {{to_string(trainer->options().augment), result.history}});
  std::filesystem::remove(checkpoint);  // the model is complete: nothing left to resume
  return result;
}

}  // namespace eitbench
