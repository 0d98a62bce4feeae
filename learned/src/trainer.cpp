#include "eitbench/learned/trainer.h"

#include "backend.h"

namespace eitbench {

Trainer::Trainer(const NetworkOptions& network, const TrainingOptions& options,
                 LabelledFrames train, const LabelledFrames& validation,
                 const AugmentSetup& sensor) {
  network.validate();  // before LibTorch is loaded: bad options cost nothing
  options.validate();
  impl_ = learned_backend().new_trainer(network, options, std::move(train), validation, sensor);
}

std::unique_ptr<Trainer> Trainer::resume(const std::string& checkpoint, const std::string& source,
                                         LabelledFrames train, const LabelledFrames& validation,
                                         const AugmentSetup& sensor) {
  return std::unique_ptr<Trainer>(new Trainer(
      learned_backend().resume_trainer(checkpoint, source, std::move(train), validation, sensor)));
}

Trainer::Trainer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Trainer::~Trainer() = default;

void Trainer::start_from(const LearnedModel& model, const std::string& source) {
  impl_->start_from(model.impl(), source);
}
bool Trainer::done() const {
  return impl_->done();
}
bool Trainer::converged() const {
  return impl_->converged();
}
TrainingRecord Trainer::run_round(const StepCallback& on_step) {
  return impl_->run_round(on_step);
}
const std::vector<TrainingRecord>& Trainer::history() const {
  return impl_->history();
}
int Trainer::best_round() const {
  return impl_->best_round();
}
int Trainer::best_epoch() const {
  return impl_->best_epoch();
}
long long Trainer::steps_per_epoch() const {
  return impl_->steps_per_epoch();
}
long long Trainer::steps_per_round() const {
  return impl_->steps_per_round();
}
long long Trainer::total_steps() const {
  return impl_->total_steps();
}
int Trainer::total_epochs() const {
  return impl_->total_epochs();
}
long long Trainer::samples_per_epoch() const {
  return impl_->samples_per_epoch();
}
const TrainingOptions& Trainer::options() const {
  return impl_->options();
}
const LearningRateSchedule& Trainer::schedule() const {
  return impl_->schedule();
}
std::string Trainer::checkpoint() const {
  return impl_->checkpoint();
}
LearnedModel Trainer::best_model() const {
  return LearnedModel(impl_->best_model());
}
Eigen::VectorXd Trainer::input_mean() const {
  return impl_->input_mean();
}
Eigen::VectorXd Trainer::input_std() const {
  return impl_->input_std();
}
void Trainer::batch(int epoch, long long index, SampleMatrix& frames, SampleMatrix& labels) const {
  impl_->batch(epoch, index, frames, labels);
}

}  // namespace eitbench
