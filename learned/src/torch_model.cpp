#include <ATen/CPUGeneratorImpl.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "eitbench/jacobian/error.h"
#include "torch_model.h"

namespace eitbench {
namespace {

constexpr const char* kModelFormat = "eitbench-learned-model-1";

// The shapes of every parameter and buffer, to check a loaded archive against: LibTorch's
// Module::load replaces a tensor by whatever the file holds, whatever its shape.
std::vector<std::pair<std::string, std::vector<long>>> shapes(const Network& net) {
  std::vector<std::pair<std::string, std::vector<long>>> out;
  for (const auto& p : net->named_parameters(true))
    out.emplace_back(p.key(), p.value().sizes().vec());
  for (const auto& b : net->named_buffers(true)) out.emplace_back(b.key(), b.value().sizes().vec());
  return out;
}

// A matrix as rows of numbers (current patterns' injection and measurement matrices), and back:
// InputError(source, "meta") for anything but equal rows of finite numbers, at most 1024 x 4096.
nlohmann::json matrix_json(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    std::vector<double> row(static_cast<std::size_t>(m.cols()));
    for (Eigen::Index j = 0; j < m.cols(); ++j) row[static_cast<std::size_t>(j)] = m(i, j);
    rows.push_back(row);
  }
  return rows;
}

Eigen::MatrixXd matrix_from_json(const nlohmann::json& rows, const std::string& source) {
  const auto bad = [&] {
    return InputError(source, "meta", "a protocol matrix is not rows of finite numbers");
  };
  if (!rows.is_array() || rows.empty() || rows.size() > 1024 || !rows[0].is_array() ||
      rows[0].empty() || rows[0].size() > 4096)
    throw bad();
  Eigen::MatrixXd m(static_cast<Eigen::Index>(rows.size()),
                    static_cast<Eigen::Index>(rows[0].size()));
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    const auto& row = rows[static_cast<std::size_t>(i)];
    if (!row.is_array() || row.size() != static_cast<std::size_t>(m.cols())) throw bad();
    for (Eigen::Index j = 0; j < m.cols(); ++j) {
      const auto& v = row[static_cast<std::size_t>(j)];
      if (!v.is_number() || !std::isfinite(v.get<double>())) throw bad();
      m(i, j) = v.get<double>();
    }
  }
  return m;
}

}  // namespace

TorchModel::TorchModel(const NetworkOptions& network, int electrodes, std::uint64_t seed) {
  network.validate();
  info.network = network;
  info.electrodes = electrodes;
  // LibTorch initialises weights from its process-wide generator: seed it for these weights, then
  // give it back its state, so that making a model (Trainer::best_model() makes one) changes no
  // other random numbers of the process.
  at::Generator generator = at::detail::getDefaultCPUGenerator();
  const torch::Tensor state = generator.get_state();
  torch::manual_seed(seed);
  net = Network(network);
  generator.set_state(state);
  net->eval();  // a model reconstructs; only the trainer's own networks train
}

std::unique_ptr<LearnedModel::Impl> TorchModel::clone() const {
  auto copy = std::make_unique<TorchModel>();
  copy->info = info;
  copy->on = on;
  copy->net = Network(info.network);
  copy->net->to(on);
  copy_state(net, copy->net);
  copy->net->eval();
  return copy;
}

long long TorchModel::parameters() const {
  long long n = 0;
  for (const auto& p : net->parameters()) n += p.numel();
  return n;
}

std::vector<bool> TorchModel::image_mask() const {
  const torch::Tensor m = net->mask.to(torch::kCPU).contiguous();
  std::vector<bool> out(static_cast<std::size_t>(m.numel()));
  const float* v = m.data_ptr<float>();
  for (std::size_t p = 0; p < out.size(); ++p) out[p] = v[p] > 0.5f;
  return out;
}

void TorchModel::to_device(const std::string& device) {
  on = torch::Device(resolve_device(device, "device"));
  net->to(on);
}

std::string TorchModel::device() const {
  return on.str();
}

SampleMatrix TorchModel::reconstruct(const SampleMatrix& frames, int batch) const {
  const NetworkOptions& o = info.network;
  if (frames.cols() != o.inputs)
    throw InputError("frames", "length",
                     std::to_string(frames.cols()) + " values a frame, but the model takes " +
                         std::to_string(o.inputs));
  if (!frames.allFinite()) throw InputError("frames", "values", "NaN or infinite values");
  SampleMatrix images(frames.rows(), o.image_size * o.image_size);
  if (frames.rows() == 0) return images;
  // No eval() here: this is const, and the mode is set once when the model is made (eval() writes
  // every module's flag, a data race between threads sharing the model).
  torch::InferenceMode guard;
  Network shared = net;  // the same module; its forward() is not const
  batch = std::max(1, batch);
  for (Eigen::Index start = 0; start < frames.rows(); start += batch) {
    const Eigen::Index rows = std::min<Eigen::Index>(batch, frames.rows() - start);
    const SampleMatrix part = frames.middleRows(start, rows);
    images.middleRows(start, rows) = to_samples(shared->forward(to_tensor(part, on)));
  }
  return images;
}

std::string TorchModel::to_bytes() const {
  torch::serialize::OutputArchive archive, weights;
  const ModelInfo& i = info;
  nlohmann::json meta = {{"electrodes", i.electrodes},
                         {"augment", i.augment},
                         {"training", nlohmann::json::parse(i.training)}};
  if (i.protocol && i.protocol->has_patterns()) {
    const CurrentPatterns& c = i.protocol->patterns();
    meta["protocol"] = {{"name", i.protocol->name()},
                        {"injection", matrix_json(c.injection)},
                        {"measurement", matrix_json(c.measurement)}};
  } else if (i.protocol) {
    nlohmann::json channels = nlohmann::json::array();
    for (const Channel& c : i.protocol->channels())
      channels.push_back({c.drive_plus, c.drive_minus, c.meas_plus, c.meas_minus});
    meta["protocol"] = {{"name", i.protocol->name()},
                        {"magnitude", i.protocol->magnitude()},
                        {"channels", channels}};
  }
  if (i.image_inputs > 0) meta["image_inputs"] = i.image_inputs;
  archive.write("format", c10::IValue(std::string(kModelFormat)));
  archive.write("network", c10::IValue(network_to_json(i.network)));
  archive.write("meta", c10::IValue(meta.dump()));
  net->save(weights);
  archive.write("weights", weights);
  std::ostringstream out;
  archive.save_to(out);
  return out.str();
}

std::unique_ptr<TorchModel> TorchModel::from_bytes(const std::string& bytes,
                                                   const std::string& source) {
  auto impl = std::make_unique<TorchModel>();
  torch::serialize::InputArchive archive, weights;
  c10::IValue format, network, meta;
  try {
    std::istringstream in(bytes);
    archive.load_from(in, torch::kCPU);
    if (!archive.try_read("format", format) || !format.isString() ||
        format.toStringRef() != kModelFormat)
      throw InputError(source, "format",
                       "not an eitbench model file (a training checkpoint, or another program's "
                       "file?)");
    archive.read("network", network);
    archive.read("meta", meta);
    archive.read("weights", weights);
  } catch (const InputError&) {
    throw;
  } catch (const c10::Error& e) {
    throw InputError(source, "", "not a readable model file (" + first_line(e) + ")");
  } catch (const std::exception& e) {  // the archive's TorchScript code, damaged
    throw InputError(source, "", "not a readable model file (" + first_line(e) + ")");
  }
  if (!network.isString() || !meta.isString())
    throw InputError(source, "meta", "the model's description is missing");
  impl->info.network = network_from_json(network.toStringRef(), source);
  try {
    const auto j = nlohmann::json::parse(meta.toStringRef());
    impl->info.electrodes = j.at("electrodes").get<int>();
    impl->info.augment = j.at("augment").get<std::string>();
    impl->info.training = j.at("training").dump();
    impl->info.image_inputs = j.value("image_inputs", 0);
    if (j.contains("protocol") && j.at("protocol").contains("injection")) {
      const auto& p = j.at("protocol");
      CurrentPatterns c{matrix_from_json(p.at("injection"), source),
                        matrix_from_json(p.at("measurement"), source)};
      impl->info.protocol = std::make_shared<const MeasurementProtocol>(
          p.at("name").get<std::string>(), std::move(c), source + ": protocol");
    } else if (j.contains("protocol")) {
      const auto& p = j.at("protocol");
      std::vector<Channel> channels;
      for (const auto& c : p.at("channels")) {
        int e[4];
        for (int k = 0; k < 4; ++k) {
          const auto& v = c.at(k);  // an electrode index: checked before it is cast
          if (!v.is_number_integer() || v.get<long long>() < 0 || v.get<long long>() > 1024)
            throw InputError(source, "meta", "a protocol channel holds a non-index value");
          e[k] = v.get<int>();
        }
        channels.push_back({e[0], e[1], e[2], e[3]});
      }
      impl->info.protocol = std::make_shared<const MeasurementProtocol>(
          MeasurementProtocol(p.at("name").get<std::string>(), impl->info.electrodes, channels,
                              source + ": protocol")
              .with_magnitude(p.at("magnitude").get<bool>()));
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, "meta", std::string("unreadable: ") + e.what());
  }
  // A protocol needs 4 electrodes, and the network reads a frame's inputs (or an image's).
  const int L = impl->info.electrodes;
  if (L < 4 || L > 1024)
    throw InputError(source, "electrodes", std::to_string(L) + " is not between 4 and 1024");
  if (impl->info.image_inputs < 0) throw InputError(source, "image_inputs", "must not be negative");
  const bool image = impl->info.image_inputs > 0;
  const int inputs = image                 ? impl->info.image_inputs
                     : impl->info.protocol ? impl->info.protocol->input_size()
                                           : L * (L - 3) / 2;
  if (impl->info.network.inputs != inputs)
    throw InputError(source, "network",
                     "takes " + std::to_string(impl->info.network.inputs) + " values, but its " +
                         (image ? "image_inputs say " : "protocol gives ") +
                         std::to_string(inputs));
  impl->net = Network(impl->info.network);
  const auto expected = shapes(impl->net);
  try {
    impl->net->load(weights);
  } catch (const c10::Error& e) {
    throw InputError(source, "weights", first_line(e));
  } catch (const std::exception& e) {
    throw InputError(source, "weights", first_line(e));
  }
  if (shapes(impl->net) != expected)
    throw InputError(source, "weights", "tensor shapes differ from the network's description");
  for (const auto& p : impl->net->named_parameters(true))
    if (!torch::isfinite(p.value()).all().item<bool>())
      throw InputError(source, "weights", p.key() + " holds NaN or infinite values");
  for (const auto& b : impl->net->named_buffers(true))
    if (b.value().is_floating_point() && !torch::isfinite(b.value()).all().item<bool>())
      throw InputError(source, "weights", b.key() + " holds NaN or infinite values");
  impl->net->eval();
  return impl;
}

}  // namespace eitbench
