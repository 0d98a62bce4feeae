// The trainer's state as data: options and history as JSON, the checkpoint and its resumption.
#include <cstring>
#include <sstream>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/random.h"
#include "train_step.h"
#include "trainer_impl.h"

namespace eitbench {
namespace {

// 2: rounds (validation at a fixed interval of samples), the schedule, early stopping's state.
constexpr const char* kCheckpointFormat = "eitbench-checkpoint-2";

}  // namespace

// A hash of everything a set's samples depend on: frames and labels, and the circles and
// background that re-rasterise the labels of augmented samples.
std::uint64_t fingerprint(const LabelledFrames& set) {
  std::uint64_t h = mix64(static_cast<std::uint64_t>(set.frames.rows()) * 31 +
                          static_cast<std::uint64_t>(set.frames.cols()));
  auto add_number = [&](double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    h = mix64(h ^ bits);
  };
  auto add = [&](const SampleMatrix& m) {
    for (Eigen::Index k = 0; k < m.size(); ++k) add_number(m.data()[k]);
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
          {"schedule", to_string(o.schedule.kind)},
          {"warmup_fraction", o.schedule.warmup_fraction},
          {"decay_fraction", o.schedule.decay_fraction},
          {"final_fraction", o.schedule.final_fraction},
          {"validate_every", o.validate_every},
          {"patience", o.patience},
          {"min_improvement", o.min_improvement},
          {"patience_after_decay", o.patience_after_decay},
          {"seed", o.seed},
          {"device", o.device},
          {"resident", o.resident},
          {"resident_max_gib", o.resident_max_gib},
          {"precision", o.precision},
          {"cuda_graphs", o.cuda_graphs},
          {"channels_last", o.channels_last}};
}

TrainingOptions options_from_json(const nlohmann::json& j) {
  TrainingOptions o;
  o.augment = parse_group(j.at("augment").get<std::string>(), "checkpoint");
  o.expanded = j.at("expanded").get<bool>();
  o.epochs = j.at("epochs").get<int>();
  o.steps = j.at("steps").get<long long>();
  o.batch_size = j.at("batch_size").get<int>();
  o.learning_rate = j.at("learning_rate").get<double>();
  o.schedule.kind = parse_schedule(j.at("schedule").get<std::string>(), "checkpoint");
  o.schedule.warmup_fraction = j.at("warmup_fraction").get<double>();
  o.schedule.decay_fraction = j.at("decay_fraction").get<double>();
  o.schedule.final_fraction = j.at("final_fraction").get<double>();
  o.validate_every = j.at("validate_every").get<long long>();
  o.patience = j.at("patience").get<int>();
  o.min_improvement = j.at("min_improvement").get<double>();
  // Not in checkpoints before a doubling waited for its floor.
  o.patience_after_decay = j.value("patience_after_decay", false);
  o.seed = j.at("seed").get<std::uint64_t>();
  o.device = j.at("device").get<std::string>();
  // Not in checkpoints before residency existed; it never changes the batches.
  o.resident = j.value("resident", o.resident);
  o.resident_max_gib = j.value("resident_max_gib", o.resident_max_gib);
  // Nor these, before GPU training was tuned.
  o.precision = j.value("precision", o.precision);
  o.cuda_graphs = j.value("cuda_graphs", o.cuda_graphs);
  o.channels_last = j.value("channels_last", o.channels_last);
  return o;
}

std::string TorchTrainer::checkpoint() const {
  const TrainerState& m = *state_;
  const nlohmann::json state = {{"network", nlohmann::json::parse(network_to_json(m.network))},
                                {"options", options_to_json(m.options)},
                                {"train_fingerprint", m.train_print},
                                {"validation_fingerprint", m.validation_print},
                                {"rounds_done", m.rounds_done},
                                {"steps_done", m.steps_done},
                                {"samples_done", m.samples_done},
                                {"best_round", m.best_round},
                                {"best_loss", finite_or_null(m.best_loss)},
                                {"reference_loss", finite_or_null(m.reference_loss)},
                                {"improved_round", m.improved_round},
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

namespace {

// The progress fields of a checkpoint's state into a freshly made trainer.
void restore_progress(const nlohmann::json& state, TrainerState& m, const std::string& source) {
  if (state.at("train_fingerprint").get<std::uint64_t>() != m.train_print ||
      state.at("validation_fingerprint").get<std::uint64_t>() != m.validation_print)
    throw InputError(source, "data",
                     "the checkpoint was made on other data (training or validation set "
                     "differs): start a new run instead of resuming");
  m.rounds_done = state.at("rounds_done").get<int>();
  m.steps_done = state.at("steps_done").get<long long>();
  m.samples_done = state.at("samples_done").get<long long>();
  m.best_round = state.at("best_round").get<int>();
  m.best_loss = number_or_infinity(state.at("best_loss"));
  m.reference_loss = number_or_infinity(state.at("reference_loss"));
  m.improved_round = state.at("improved_round").get<int>();
  m.stopped_early = state.at("stopped_early").get<bool>();
  m.history = history_from_json(state.at("history").dump(), source);
}

// Adam's state follows the parameters onto their device: the archive was read onto the CPU, and a
// CUDA resume would otherwise mix devices at the first step.
void move_optimizer_state(torch::optim::Adam& adam, const torch::Device& device) {
  for (auto& [key, state] : adam.state()) {
    auto& s = static_cast<torch::optim::AdamParamState&>(*state);
    s.exp_avg(s.exp_avg().to(device));
    s.exp_avg_sq(s.exp_avg_sq().to(device));
    if (s.max_exp_avg_sq().defined()) s.max_exp_avg_sq(s.max_exp_avg_sq().to(device));
  }
}

}  // namespace

void TrainerState::lay_out() {
  const bool on = options.channels_last == "on";
  net->use_channels_last(on);
  best->use_channels_last(on);
  torch::NoGradGuard no_grad;
  for (const auto& p : net->parameters()) {
    if (auto* s = adam_state_if_any(*adam, p)) {
      s->exp_avg(torch::empty_like(p).copy_(s->exp_avg()));
      s->exp_avg_sq(torch::empty_like(p).copy_(s->exp_avg_sq()));
    }
  }
}

std::unique_ptr<TorchTrainer> TorchTrainer::resume(const std::string& bytes,
                                                   const std::string& source, LabelledFrames train,
                                                   const LabelledFrames& validation,
                                                   const AugmentSetup& sensor) {
  torch::serialize::InputArchive archive, net, best, adam;
  c10::IValue format, state_text;
  try {
    std::istringstream in(bytes);
    archive.load_from(in, torch::kCPU);
    if (!archive.try_read("format", format) || !format.isString())
      throw InputError(source, "format", "not an eitbench training checkpoint");
    if (format.toStringRef() != kCheckpointFormat)
      throw InputError(source, "format",
                       "a checkpoint of another eitbench version (" + format.toStringRef() +
                           "): start a new run instead of resuming");
    archive.read("state", state_text);
    archive.read("net", net);
    archive.read("best", best);
    archive.read("optimizer", adam);
  } catch (const InputError&) {
    throw;
  } catch (const c10::Error& e) {
    throw InputError(source, "", "not a readable checkpoint (" + first_line(e) + ")");
  } catch (const std::exception& e) {  // the archive's TorchScript code, damaged
    throw InputError(source, "", "not a readable checkpoint (" + first_line(e) + ")");
  }
  std::unique_ptr<TrainerState> m;
  try {
    const auto state = nlohmann::json::parse(state_text.toStringRef());
    const TrainingOptions options = options_from_json(state.at("options"));
    try {
      options.validate();  // the checkpoint's options, not the caller's: the error names the file
    } catch (const InputError& e) {
      throw InputError(source, "options", e.field() + ": " + e.message());
    }
    m = std::make_unique<TrainerState>(network_from_json(state.at("network").dump(), source),
                                       options, std::move(train), validation, sensor);
    restore_progress(state, *m, source);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, "state", std::string("unreadable: ") + e.what());
  }
  try {
    m->net->load(net);
    m->best->load(best);
    m->net->to(m->device);
    m->best->to(m->device);
    m->adam->load(adam);
    move_optimizer_state(*m->adam, m->device);
    m->lay_out();  // loading adopts the stored tensors, in the layout they were saved in
  } catch (const c10::Error& e) {
    throw InputError(source, "weights", first_line(e));
  } catch (const std::exception& e) {
    throw InputError(source, "weights", first_line(e));
  }
  return std::make_unique<TorchTrainer>(std::move(m));
}

}  // namespace eitbench
