#include "trainer_impl.h"

#include <chrono>
#include <cmath>
#include <tuple>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/random.h"
#include "torch_model.h"

namespace eitbench {

TrainerState::TrainerState(const NetworkOptions& n, const TrainingOptions& o,
                           LabelledFrames train_set, const LabelledFrames& validation,
                           const AugmentSetup& sensor)
    : network(n),
      options(o),
      setup(sensor),
      train(std::make_shared<const LabelledFrames>(std::move(train_set))) {
  network.validate();
  options.validate();
  setup.group = options.augment;
  setup.layout = FrameLayout::reduced;
  if (train->frames.rows() == 0) throw InputError("train", "split", "the training set is empty");
  if (validation.frames.rows() == 0)
    throw InputError("validation", "split", "the validation set is empty");
  auto labelled = [](const LabelledFrames& s) { return s.labels.cols() > 0 || !s.circles.empty(); };
  if (!labelled(*train)) throw InputError("train", "labels", "training needs labelled frames");
  if (!labelled(validation))
    throw InputError("validation", "labels", "validation needs labelled frames");
  if (setup.image_size != network.image_size)
    throw InputError("network", "image_size",
                     "the network draws " + std::to_string(network.image_size) +
                         " px images, the data's labels are " + std::to_string(setup.image_size));
  check_labelled_frames(*train, setup);  // frame length against the electrodes, labels' shape
  check_labelled_frames(validation, setup);
  if (train->frames.cols() != network.inputs)
    throw InputError("network", "inputs",
                     "the network takes " + std::to_string(network.inputs) +
                         " values, frames have " + std::to_string(train->frames.cols()));
  device = torch::Device(resolve_device(options.device, "TrainingOptions"));

  // Validation frames as they are (no augmentation); labels from the circles when not stored.
  AugmentSetup plain = setup;
  plain.group = AugmentGroup::none;
  const OnTheFlyAugmenter identity(std::make_shared<const LabelledFrames>(validation), plain, 0);
  std::vector<int> all(static_cast<std::size_t>(validation.frames.rows()));
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  identity.batch(all, 0, validation_frames, validation_labels);
  train_print = fingerprint(*train);
  validation_print = fingerprint(validation);

  group_size = static_cast<int>(augment_elements(setup).size());
  if (options.expanded) {
    expanded = expand_by_group(*train, setup);
    train_size = expanded.frames.rows();
  } else {
    augmenter = std::make_unique<OnTheFlyAugmenter>(train, setup, options.seed);
    train_size = train->frames.rows();
  }
  if (train_size < 2) throw InputError("train", "split", "training needs at least 2 samples");
  if (choose_residency()) make_resident();
  graphs = choose_graphs();
  if (device.is_cuda())
    cuda::set_math(resolve_precision(options.precision, device) != "fp32", true);
  const long long b = options.batch_size;
  steps_per_epoch = eitbench::steps_per_epoch(train_size, options.batch_size);
  steps_per_round = (options.validate_every + b - 1) / b;
  if (options.steps > 0) {
    total_steps = options.steps;
    total_epochs = static_cast<int>((total_steps + steps_per_epoch - 1) / steps_per_epoch);
  } else {
    total_epochs = options.epochs > 0 ? options.epochs : 20;
    total_steps = total_epochs * steps_per_epoch;
  }
  schedule = std::make_unique<LearningRateSchedule>(options.learning_rate, total_steps,
                                                    options.schedule, "Trainer");

  input_statistics();
  torch::manual_seed(options.seed);
  net = Network(network);
  best = Network(network);
  {
    torch::NoGradGuard no_grad;
    net->mean.copy_(torch::from_blob(mean.data(), {mean.size()}, torch::kFloat64));
    net->scale.copy_(torch::from_blob(Eigen::VectorXd(std.cwiseInverse()).data(), {std.size()},
                                      torch::kFloat64));
  }
  net->to(device);
  best->to(device);
  copy_state(net, best);
  adam = std::make_unique<torch::optim::Adam>(net->parameters(),
                                              torch::optim::AdamOptions(options.learning_rate));
  lay_out();
}

// Mean and standard deviation of every input over the augmented training set. A frame's orbit is
// the frame gathered through one signed index table per group element, so the orbit's moments
// follow from the plain per-input moments, gathered: O(N d + |G| d) work instead of O(N |G| d).
// With m0, Q the plain mean and centred sum of squares of input j, and t a table, the augmented
// input i collects sum_t (Q[t_i] + N (m0[t_i] - mean_i)^2) about its mean: no cancellation.
void TrainerState::input_statistics() {
  const auto actions = frame_actions(setup);  // signed gathers, one per group element
  const SampleMatrix& x = train->frames;
  const Eigen::Index d = x.cols();
  const double n = double(x.rows()), count = n * double(actions.size());
  const Eigen::VectorXd m0 = x.colwise().mean().transpose();
  const Eigen::VectorXd q = (x.rowwise() - m0.transpose()).colwise().squaredNorm().transpose();
  mean = Eigen::VectorXd::Zero(d);
  for (const auto& a : actions)
    for (Eigen::Index i = 0; i < d; ++i) mean[i] += a.sign[i] * m0[a.index[i]];
  mean /= double(actions.size());
  Eigen::VectorXd square = Eigen::VectorXd::Zero(d);
  for (const auto& a : actions)
    for (Eigen::Index i = 0; i < d; ++i) {
      const double moved = a.sign[i] * m0[a.index[i]];  // a sign flips the mean, not Q
      square[i] += q[a.index[i]] + n * (moved - mean[i]) * (moved - mean[i]);
    }
  std = (square / count).cwiseSqrt();
  // A constant input (e.g. a single frame) would divide by zero: scale it by 1.
  const double floor = 1e-12 * std::max(std.maxCoeff(), 1e-300);
  for (Eigen::Index k = 0; k < d; ++k)
    if (!(std[k] > floor)) std[k] = 1.0;
}

void TrainerState::make_batch(int epoch, const std::vector<long long>& order, long long index,
                              SampleMatrix& frames, SampleMatrix& labels) const {
  const long long b = options.batch_size, start = index * b,
                  end = std::min<long long>(start + b, train_size);
  if (options.expanded) {
    frames.resize(end - start, expanded.frames.cols());
    labels.resize(end - start, expanded.labels.cols());
    for (long long k = start; k < end; ++k) {
      frames.row(k - start) = expanded.frames.row(order[k]);
      labels.row(k - start) = expanded.labels.row(order[k]);
    }
  } else {
    std::vector<int> indices;
    for (long long k = start; k < end; ++k) indices.push_back(static_cast<int>(order[k]));
    augmenter->batch(indices, epoch, frames, labels);
  }
}

double TrainerState::validate() {
  torch::InferenceMode guard;
  net->eval();
  double total = 0;
  const Eigen::Index rows = validation_frames.rows(), step = 512;
  for (Eigen::Index start = 0; start < rows; start += step) {
    const Eigen::Index n = std::min(step, rows - start);
    const auto out = net->forward(to_tensor(validation_frames.middleRows(start, n), device));
    const auto truth = to_tensor(validation_labels.middleRows(start, n), device);
    total += (out - truth).square().sum().item<double>();
  }
  return total / (double(rows) * double(validation_labels.cols()));
}

// Keeps the best model, and stops after `patience` rounds without a real improvement: a loss that
// creeps down by less than min_improvement a round is a plateau, not progress worth its time.
void TrainerState::record_validation(const TrainingRecord& r) {
  if (r.validation_loss < best_loss) {
    best_loss = r.validation_loss;
    best_round = r.round;
    copy_state(net, best);
  }
  // The first finite loss always counts (reference_loss starts at infinity); a NaN never does.
  if (r.validation_loss < reference_loss * (1 - options.min_improvement)) {
    reference_loss = r.validation_loss;
    improved_round = r.round;
  } else if (options.patience > 0 && r.round - improved_round >= options.patience &&
             (!options.patience_after_decay || r.steps >= schedule->decay_steps())) {
    stopped_early = true;
  }
}

void TorchTrainer::start_from(const LearnedModel::Impl& model, const std::string& source) {
  TrainerState& m = *state_;
  if (m.rounds_done > 0)
    throw InputError(source, "network", "fine-tuning starts before the first round");
  const Network& from = static_cast<const TorchModel&>(model).net;
  const auto theirs = from->named_parameters(true), ours = m.net->named_parameters(true);
  bool same = theirs.size() == ours.size();
  for (const auto& p : theirs)
    same = same && ours.contains(p.key()) && ours[p.key()].sizes() == p.value().sizes();
  if (!same || from->mean.size(0) != m.net->mean.size(0))
    throw InputError(source, "network",
                     "is not the network being trained (another size or input length)");
  copy_state(from, m.net);
  copy_state(from, m.best);
  const torch::Tensor mean = m.net->mean.to(torch::kCPU, torch::kFloat64).contiguous();
  const torch::Tensor scale = m.net->scale.to(torch::kCPU, torch::kFloat64).contiguous();
  m.mean = Eigen::Map<const Eigen::VectorXd>(mean.data_ptr<double>(), mean.size(0));
  m.std = Eigen::Map<const Eigen::VectorXd>(scale.data_ptr<double>(), scale.size(0)).cwiseInverse();
}

bool TorchTrainer::done() const {
  return state_->stopped_early || state_->steps_done >= state_->total_steps;
}
bool TorchTrainer::converged() const {
  return state_->stopped_early;
}

TrainingRecord TorchTrainer::run_round(const StepCallback& on_step) {
  TrainerState& m = *state_;
  if (done()) throw std::logic_error("Trainer::run_round: the budget is spent");
  const int round = m.rounds_done + 1;
  const long long steps = std::min(m.steps_per_round, m.total_steps - m.steps_done);
  // Dropout's random numbers: a function of (seed, round), so a resumed run draws the same.
  torch::manual_seed(mix64(m.options.seed ^ mix64(static_cast<std::uint64_t>(round))));
  m.net->train();
  SampleMatrix frames, labels;
  std::vector<long long> order;
  torch::Tensor rows;  // order's rows on the device, when resident
  int epoch = 0;       // of `order`
  double rate = 0;
  long long samples = 0;
  // The batch losses add up on the device: reading one forces a device sync, so the sum is read
  // only when on_step is due (at most 64 times a round) and at the end of the round.
  if (!m.runner)
    m.runner = std::make_unique<StepRunner>(m.net, *m.adam, m.options, m.device, m.graphs);
  StepRunner& runner = *m.runner;
  runner.reset_loss();
  const long long report_every = std::max<long long>(1, (steps + 63) / 64);
  double reported = 0;
  long long reported_steps = 0;
  const auto start = std::chrono::steady_clock::now();
  for (long long s = 0; s < steps; ++s) {
    const long long step = m.steps_done + s;
    const int step_epoch = static_cast<int>(step / m.steps_per_epoch) + 1;
    if (step_epoch != epoch) {
      epoch = step_epoch, order = permutation(m.train_size, m.options.seed, epoch);
      if (m.resident) rows = m.resident_rows(epoch, order);
    }
    const long long index = step % m.steps_per_epoch;
    rate = m.schedule->rate(step);
    if (m.resident) {
      const long long b = m.options.batch_size, first = index * b,
                      end = std::min(first + b, m.train_size);
      runner.step(*m.resident, rows, first, end, rate);
      samples += end - first;
    } else {
      m.make_batch(epoch, order, index, frames, labels);
      runner.step(to_tensor(frames, m.device), to_tensor(labels, m.device), rate);
      samples += frames.rows();
    }
    if (on_step && ((s + 1) % report_every == 0 || s + 1 == steps)) {
      const double total = runner.loss_sum().item<double>();
      on_step(s + 1, steps, (total - reported) / double(s + 1 - reported_steps));
      reported = total, reported_steps = s + 1;
    }
  }
  runner.sync_optimizer();
  const double loss_sum = runner.loss_sum().item<double>();  // waits for the round's last step
  TrainingRecord r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.round = m.rounds_done = round;
  m.steps_done += steps;
  m.samples_done += samples;
  r.epoch = static_cast<int>((m.steps_done + m.steps_per_epoch - 1) / m.steps_per_epoch);
  r.steps = m.steps_done;
  r.samples = m.samples_done;
  r.train_loss = loss_sum / double(steps);
  r.learning_rate = rate;
  r.samples_per_second = r.seconds > 0 ? samples / r.seconds : 0;
  r.validation_loss = m.validate();
  m.record_validation(r);
  m.history.push_back(r);
  return r;
}

const std::vector<TrainingRecord>& TorchTrainer::history() const {
  return state_->history;
}
int TorchTrainer::best_round() const {
  return state_->best_round;
}
int TorchTrainer::best_epoch() const {
  return state_->best_round > 0 ? state_->history[state_->best_round - 1].epoch : 0;
}
long long TorchTrainer::steps_per_epoch() const {
  return state_->steps_per_epoch;
}
long long TorchTrainer::steps_per_round() const {
  return state_->steps_per_round;
}
long long TorchTrainer::total_steps() const {
  return state_->total_steps;
}
int TorchTrainer::total_epochs() const {
  return state_->total_epochs;
}
long long TorchTrainer::samples_per_epoch() const {
  return state_->train_size;
}
const TrainingOptions& TorchTrainer::options() const {
  return state_->options;
}
const LearningRateSchedule& TorchTrainer::schedule() const {
  return *state_->schedule;
}
Eigen::VectorXd TorchTrainer::input_mean() const {
  return state_->mean;
}
Eigen::VectorXd TorchTrainer::input_std() const {
  return state_->std;
}

void TorchTrainer::batch(int epoch, long long index, SampleMatrix& frames,
                         SampleMatrix& labels) const {
  if (epoch < 1 || index < 0 || index >= state_->steps_per_epoch)
    throw std::out_of_range("Trainer::batch: no such batch");
  const TrainerState& m = *state_;
  const auto order = permutation(m.train_size, m.options.seed, epoch);
  if (!m.resident) return m.make_batch(epoch, order, index, frames, labels);
  const long long b = m.options.batch_size, first = index * b;
  const auto [x, y] =
      m.resident->batch(m.resident_rows(epoch, order), first, std::min(first + b, m.train_size));
  frames = to_samples(x), labels = to_samples(y);
}

std::unique_ptr<LearnedModel::Impl> TorchTrainer::best_model() const {
  const TrainerState& m = *state_;
  auto model = std::make_unique<TorchModel>(m.network, m.setup.electrodes, m.options.seed);
  copy_state(m.best_round > 0 ? m.best : m.net, model->net);
  ModelInfo& info = model->info;
  info.augment = to_string(m.options.augment);
  info.protocol = m.setup.protocol;
  info.image_inputs = m.setup.image_inputs;
  info.training = nlohmann::json{{"options", options_to_json(m.options)},
                                 {"train_samples", m.train->frames.rows()},
                                 {"samples_per_epoch", m.train_size},
                                 {"steps_per_epoch", m.steps_per_epoch},
                                 {"budget_steps", m.total_steps},
                                 {"rounds", m.rounds_done},
                                 {"steps", m.steps_done},
                                 {"samples", m.samples_done},
                                 {"best_round", m.best_round},
                                 {"best_epoch", best_epoch()},
                                 {"best_validation_loss", finite_or_null(m.best_loss)},
                                 {"stopped_early", m.stopped_early},
                                 {"converged", m.stopped_early},
                                 {"history", nlohmann::json::parse(history_to_json(m.history))}}
                      .dump();
  return model;
}

}  // namespace eitbench
