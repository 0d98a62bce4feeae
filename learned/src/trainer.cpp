#include "eitbench/learned/trainer.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/random.h"
#include "network.h"

namespace eitbench {
namespace {

constexpr const char* kCheckpointFormat = "eitbench-checkpoint-1";
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A hash of everything a set's samples depend on: frames and labels, and the circles and
// background that re-rasterise the labels of augmented samples. A checkpoint only resumes on the
// data it was made with.
std::uint64_t fingerprint(const LabelledFrames& set) {
  std::uint64_t h = mix64(static_cast<std::uint64_t>(set.frames.rows()) * 31 +
                          static_cast<std::uint64_t>(set.frames.cols()));
  auto add = [&](const SampleMatrix& m) {
    for (Eigen::Index k = 0; k < m.size(); ++k) {
      std::uint64_t bits;
      std::memcpy(&bits, m.data() + k, sizeof bits);
      h = mix64(h ^ bits);
    }
  };
  auto add_number = [&](double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    h = mix64(h ^ bits);
  };
  add(set.frames);
  add(set.labels);
  add_number(set.background);
  add_number(static_cast<double>(set.circles.size()));
  for (const auto& sample : set.circles) {
    add_number(static_cast<double>(sample.size()));
    for (const Circle& c : sample)
      add_number(c.x), add_number(c.y), add_number(c.r), add_number(c.conductivity);
  }
  return h;
}

// The order of epoch `epoch`'s samples: Fisher-Yates on the (seed, epoch) stream.
std::vector<long long> permutation(long long n, std::uint64_t seed, int epoch) {
  std::vector<long long> order(static_cast<std::size_t>(n));
  for (long long i = 0; i < n; ++i) order[i] = i;
  RandomStream random(seed, 0x0b5e55edULL + static_cast<std::uint64_t>(epoch));
  for (long long i = n - 1; i > 0; --i)
    std::swap(order[i], order[random.next() % static_cast<std::uint64_t>(i + 1)]);
  return order;
}

nlohmann::json options_to_json(const TrainingOptions& o) {
  return {{"augment", to_string(o.augment)},
          {"expanded", o.expanded},
          {"epochs", o.epochs},
          {"steps", o.steps},
          {"batch_size", o.batch_size},
          {"learning_rate", o.learning_rate},
          {"patience", o.patience},
          {"seed", o.seed},
          {"device", o.device}};
}

TrainingOptions options_from_json(const nlohmann::json& j) {
  TrainingOptions o;
  o.augment = parse_group(j.at("augment").get<std::string>(), "checkpoint");
  o.expanded = j.at("expanded").get<bool>();
  o.epochs = j.at("epochs").get<int>();
  o.steps = j.at("steps").get<long long>();
  o.batch_size = j.at("batch_size").get<int>();
  o.learning_rate = j.at("learning_rate").get<double>();
  o.patience = j.at("patience").get<int>();
  o.seed = j.at("seed").get<std::uint64_t>();
  o.device = j.at("device").get<std::string>();
  return o;
}

nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}
double number_or_infinity(const nlohmann::json& j) {
  return j.is_null() ? kInfinity : j.get<double>();
}

}  // namespace

std::string history_to_json(const std::vector<EpochRecord>& history) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& r : history)
    out.push_back({{"epoch", r.epoch},
                   {"steps", r.steps},
                   {"samples", r.samples},
                   {"train_loss", finite_or_null(r.train_loss)},
                   {"validation_loss", finite_or_null(r.validation_loss)},
                   {"seconds", r.seconds},
                   {"samples_per_second", r.samples_per_second}});
  return out.dump();
}

std::vector<EpochRecord> history_from_json(const std::string& text, const std::string& source) {
  std::vector<EpochRecord> out;
  try {
    for (const auto& e : nlohmann::json::parse(text)) {
      EpochRecord r;
      r.epoch = e.at("epoch").get<int>();
      r.steps = e.at("steps").get<long long>();
      r.samples = e.at("samples").get<long long>();
      r.train_loss = number_or_infinity(e.at("train_loss"));
      r.validation_loss = number_or_infinity(e.at("validation_loss"));
      r.seconds = e.at("seconds").get<double>();
      r.samples_per_second = e.at("samples_per_second").get<double>();
      out.push_back(r);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, "history", std::string("unreadable: ") + e.what());
  }
  return out;
}

struct Trainer::Impl {
  NetworkOptions network;
  TrainingOptions options;
  AugmentSetup setup;
  LabelledFrames train;
  LabelledFrames expanded;  // the |G| N samples, when options.expanded
  std::unique_ptr<OnTheFlyAugmenter> augmenter;
  SampleMatrix validation_frames, validation_labels;
  std::uint64_t train_print = 0, validation_print = 0;
  torch::Device device = torch::kCPU;
  Network net{nullptr}, best{nullptr};
  std::unique_ptr<torch::optim::Adam> adam;
  Eigen::VectorXd mean, std;
  long long train_size = 0, steps_per_epoch = 0, total_steps = 0;
  int total_epochs = 0;
  std::vector<EpochRecord> history;
  int epochs_done = 0, best_epoch = 0;
  long long steps_done = 0, samples_done = 0;
  double best_loss = kInfinity;
  bool stopped_early = false;

  Impl(const NetworkOptions& n, const TrainingOptions& o, LabelledFrames train_set,
       const LabelledFrames& validation, const AugmentSetup& sensor);
  void input_statistics();
  void make_batch(int epoch, const std::vector<long long>& order, long long index,
                  SampleMatrix& frames, SampleMatrix& labels) const;
  double validate();
};

Trainer::Impl::Impl(const NetworkOptions& n, const TrainingOptions& o, LabelledFrames train_set,
                    const LabelledFrames& validation, const AugmentSetup& sensor)
    : network(n), options(o), setup(sensor), train(std::move(train_set)) {
  check_network_options(network, "network");
  setup.group = options.augment;
  setup.layout = FrameLayout::reduced;
  if (train.frames.rows() == 0) throw InputError("train", "split", "the training set is empty");
  if (validation.frames.rows() == 0)
    throw InputError("validation", "split", "the validation set is empty");
  auto labelled = [](const LabelledFrames& s) { return s.labels.cols() > 0 || !s.circles.empty(); };
  if (!labelled(train)) throw InputError("train", "labels", "training needs labelled frames");
  if (!labelled(validation))
    throw InputError("validation", "labels", "validation needs labelled frames");
  if (setup.image_size != network.image_size)
    throw InputError("network", "image_size",
                     "the network draws " + std::to_string(network.image_size) +
                         " px images, the data's labels are " + std::to_string(setup.image_size));
  check_labelled_frames(train, setup);  // frame length against the electrodes, labels' shape
  check_labelled_frames(validation, setup);
  if (train.frames.cols() != network.inputs)
    throw InputError("network", "inputs",
                     "the network takes " + std::to_string(network.inputs) +
                         " values, frames have " + std::to_string(train.frames.cols()));
  if (options.batch_size < 2) throw InputError("--batch", "", "must be at least 2");
  if (!(options.learning_rate > 0) || !std::isfinite(options.learning_rate))
    throw InputError("--lr", "", "must be positive");
  if (options.epochs < 0 || options.steps < 0 || options.patience < 0)
    throw InputError("budget", "", "epochs, steps and patience must not be negative");
  if (options.epochs > 0 && options.steps > 0)
    throw InputError("budget", "", "give epochs or steps, not both");
  device = torch::Device(resolve_device(options.device, "--device"));

  // Validation frames as they are (no augmentation); labels from the circles when not stored.
  AugmentSetup plain = setup;
  plain.group = AugmentGroup::none;
  const OnTheFlyAugmenter identity(validation, plain, 0);
  std::vector<int> all(static_cast<std::size_t>(validation.frames.rows()));
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  identity.batch(all, 0, validation_frames, validation_labels);
  train_print = fingerprint(train);
  validation_print = fingerprint(validation);

  if (options.expanded) {
    expanded = expand(train, setup);
    train_size = expanded.frames.rows();
  } else {
    augmenter = std::make_unique<OnTheFlyAugmenter>(train, setup, options.seed);
    train_size = train.frames.rows();
  }
  if (train_size < 2) throw InputError("train", "split", "training needs at least 2 samples");
  const long long b = options.batch_size;
  steps_per_epoch = std::max(1LL, train_size / b + (train_size % b >= 2 ? 1 : 0));
  if (options.steps > 0) {
    total_steps = options.steps;
    total_epochs = static_cast<int>((total_steps + steps_per_epoch - 1) / steps_per_epoch);
  } else {
    total_epochs = options.epochs > 0 ? options.epochs : 20;
    total_steps = total_epochs * steps_per_epoch;
  }

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
}

// Mean and standard deviation of every input over the augmented training set: each frame under
// every group element (two passes, in double; a frame's orbit is a set of permutations of it).
void Trainer::Impl::input_statistics() {
  const FrameSymmetry symmetry(setup.electrodes);
  const auto elements = group_elements(setup.group, setup.electrodes);
  const Eigen::Index d = train.frames.cols();
  const double count = double(train.frames.rows()) * double(elements.size());
  auto for_each = [&](const std::function<void(const Eigen::VectorXd&)>& f) {
    for (Eigen::Index i = 0; i < train.frames.rows(); ++i) {
      const Eigen::VectorXd frame = train.frames.row(i).transpose();
      for (const GroupElement& g : elements) f(symmetry.apply(setup.group, g, frame, setup.layout));
    }
  };
  mean = Eigen::VectorXd::Zero(d);
  for_each([&](const Eigen::VectorXd& v) { mean += v; });
  mean /= count;
  Eigen::VectorXd square = Eigen::VectorXd::Zero(d);
  for_each([&](const Eigen::VectorXd& v) { square += (v - mean).cwiseAbs2(); });
  std = (square / count).cwiseSqrt();
  // A constant input (e.g. a single frame) would divide by zero: scale it by 1.
  const double floor = 1e-12 * std::max(std.maxCoeff(), 1e-300);
  for (Eigen::Index k = 0; k < d; ++k)
    if (!(std[k] > floor)) std[k] = 1.0;
}

void Trainer::Impl::make_batch(int epoch, const std::vector<long long>& order, long long index,
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

double Trainer::Impl::validate() {
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

Trainer::Trainer(const NetworkOptions& network, const TrainingOptions& options,
                 LabelledFrames train, const LabelledFrames& validation, const AugmentSetup& sensor)
    : impl_(std::make_unique<Impl>(network, options, std::move(train), validation, sensor)) {}

Trainer::Trainer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Trainer::~Trainer() = default;

bool Trainer::done() const {
  return impl_->stopped_early || impl_->steps_done >= impl_->total_steps;
}

EpochRecord Trainer::run_epoch(const StepCallback& on_step) {
  Impl& m = *impl_;
  if (done()) throw std::logic_error("Trainer::run_epoch: the budget is spent");
  const int epoch = m.epochs_done + 1;
  const long long steps = std::min(m.steps_per_epoch, m.total_steps - m.steps_done);
  const auto order = permutation(m.train_size, m.options.seed, epoch);
  // Dropout's random numbers: a function of (seed, epoch), so a resumed run draws the same.
  torch::manual_seed(mix64(m.options.seed ^ mix64(static_cast<std::uint64_t>(epoch))));
  m.net->train();
  SampleMatrix frames, labels;
  double loss_sum = 0;
  long long samples = 0;
  const auto start = std::chrono::steady_clock::now();
  for (long long s = 0; s < steps; ++s) {
    m.make_batch(epoch, order, s, frames, labels);
    const auto x = to_tensor(frames, m.device), y = to_tensor(labels, m.device);
    m.adam->zero_grad();
    const auto loss = torch::mse_loss(m.net->forward(x), y);
    loss.backward();
    m.adam->step();
    const double value = loss.item<double>();
    loss_sum += value;
    samples += frames.rows();
    if (on_step) on_step(s + 1, steps, value);
  }
  EpochRecord r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.epoch = epoch;
  m.epochs_done = epoch;
  m.steps_done += steps;
  m.samples_done += samples;
  r.steps = m.steps_done;
  r.samples = m.samples_done;
  r.train_loss = loss_sum / double(steps);
  r.samples_per_second = r.seconds > 0 ? samples / r.seconds : 0;
  r.validation_loss = m.validate();
  if (r.validation_loss < m.best_loss) {
    m.best_loss = r.validation_loss;
    m.best_epoch = epoch;
    copy_state(m.net, m.best);
  } else if (m.options.patience > 0 && epoch - m.best_epoch >= m.options.patience) {
    m.stopped_early = true;
  }
  m.history.push_back(r);
  return r;
}

const std::vector<EpochRecord>& Trainer::history() const {
  return impl_->history;
}
int Trainer::best_epoch() const {
  return impl_->best_epoch;
}
long long Trainer::steps_per_epoch() const {
  return impl_->steps_per_epoch;
}
long long Trainer::total_steps() const {
  return impl_->total_steps;
}
int Trainer::total_epochs() const {
  return impl_->total_epochs;
}
const TrainingOptions& Trainer::options() const {
  return impl_->options;
}
Eigen::VectorXd Trainer::input_mean() const {
  return impl_->mean;
}
Eigen::VectorXd Trainer::input_std() const {
  return impl_->std;
}

void Trainer::batch(int epoch, long long index, SampleMatrix& frames, SampleMatrix& labels) const {
  if (epoch < 1 || index < 0 || index >= impl_->steps_per_epoch)
    throw std::out_of_range("Trainer::batch: no such batch");
  impl_->make_batch(epoch, permutation(impl_->train_size, impl_->options.seed, epoch), index,
                    frames, labels);
}

LearnedModel Trainer::best_model() const {
  const Impl& m = *impl_;
  LearnedModel model(m.network, m.setup.electrodes, m.options.seed);
  copy_state(m.best_epoch > 0 ? m.best : m.net, model.impl().net);
  ModelInfo& info = model.info();
  info.augment = to_string(m.options.augment);
  info.training = nlohmann::json{{"options", options_to_json(m.options)},
                                 {"train_samples", m.train.frames.rows()},
                                 {"samples_per_epoch", m.train_size},
                                 {"steps_per_epoch", m.steps_per_epoch},
                                 {"epochs", m.epochs_done},
                                 {"steps", m.steps_done},
                                 {"samples", m.samples_done},
                                 {"best_epoch", m.best_epoch},
                                 {"best_validation_loss", finite_or_null(m.best_loss)},
                                 {"stopped_early", m.stopped_early},
                                 {"history", nlohmann::json::parse(history_to_json(m.history))}}
                      .dump();
  return model;
}

std::string Trainer::checkpoint() const {
  const Impl& m = *impl_;
  const nlohmann::json state = {{"network", nlohmann::json::parse(network_to_json(m.network))},
                                {"options", options_to_json(m.options)},
                                {"train_fingerprint", m.train_print},
                                {"validation_fingerprint", m.validation_print},
                                {"epochs_done", m.epochs_done},
                                {"steps_done", m.steps_done},
                                {"samples_done", m.samples_done},
                                {"best_epoch", m.best_epoch},
                                {"best_loss", finite_or_null(m.best_loss)},
                                {"stopped_early", m.stopped_early},
                                {"history", nlohmann::json::parse(history_to_json(m.history))}};
  torch::serialize::OutputArchive archive, net, best, adam;
  archive.write("format", c10::IValue(std::string(kCheckpointFormat)));
  archive.write("state", c10::IValue(state.dump()));
  m.net->save(net);
  m.best->save(best);
  m.adam->save(adam);
  archive.write("net", net);
  archive.write("best", best);
  archive.write("optimizer", adam);
  std::ostringstream out;
  archive.save_to(out);
  return out.str();
}

std::unique_ptr<Trainer> Trainer::resume(const std::string& bytes, const std::string& source,
                                         LabelledFrames train, const LabelledFrames& validation,
                                         const AugmentSetup& sensor) {
  torch::serialize::InputArchive archive, net, best, adam;
  c10::IValue format, state_text;
  try {
    std::istringstream in(bytes);
    archive.load_from(in, torch::kCPU);
    if (!archive.try_read("format", format) || !format.isString() ||
        format.toStringRef() != kCheckpointFormat)
      throw InputError(source, "format", "not an eitbench training checkpoint");
    archive.read("state", state_text);
    archive.read("net", net);
    archive.read("best", best);
    archive.read("optimizer", adam);
  } catch (const c10::Error& e) {
    throw InputError(source, "", "not a readable checkpoint (" + first_line(e) + ")");
  }
  std::unique_ptr<Impl> m;
  nlohmann::json state;
  try {
    state = nlohmann::json::parse(state_text.toStringRef());
    m = std::make_unique<Impl>(network_from_json(state.at("network").dump(), source),
                               options_from_json(state.at("options")), std::move(train), validation,
                               sensor);
    if (state.at("train_fingerprint").get<std::uint64_t>() != m->train_print ||
        state.at("validation_fingerprint").get<std::uint64_t>() != m->validation_print)
      throw InputError(source, "data",
                       "the checkpoint was made on other data (training or validation set "
                       "differs): start a new run without --resume");
    m->epochs_done = state.at("epochs_done").get<int>();
    m->steps_done = state.at("steps_done").get<long long>();
    m->samples_done = state.at("samples_done").get<long long>();
    m->best_epoch = state.at("best_epoch").get<int>();
    m->best_loss = number_or_infinity(state.at("best_loss"));
    m->stopped_early = state.at("stopped_early").get<bool>();
    m->history = history_from_json(state.at("history").dump(), source);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, "state", std::string("unreadable: ") + e.what());
  }
  try {
    m->net->load(net);
    m->best->load(best);
    m->net->to(m->device);
    m->best->to(m->device);
    m->adam->load(adam);
    // The archive was read onto the CPU, and Adam's load keeps its state tensors where the archive
    // put them: move them to the device the parameters are on (a CUDA resume would otherwise mix
    // devices at the first step).
    for (auto& [key, state] : m->adam->state()) {
      auto& s = static_cast<torch::optim::AdamParamState&>(*state);
      s.exp_avg(s.exp_avg().to(m->device));
      s.exp_avg_sq(s.exp_avg_sq().to(m->device));
      if (s.max_exp_avg_sq().defined()) s.max_exp_avg_sq(s.max_exp_avg_sq().to(m->device));
    }
  } catch (const c10::Error& e) {
    throw InputError(source, "weights", first_line(e));
  }
  return std::unique_ptr<Trainer>(new Trainer(std::move(m)));
}

}  // namespace eitbench
