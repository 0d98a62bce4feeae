#include "eitbench/learned/learned_model.h"

#include "backend.h"

namespace eitbench {

LearnedModel::LearnedModel(const NetworkOptions& network, int electrodes, std::uint64_t seed) {
  network.validate();  // before LibTorch is loaded: a bad size costs nothing
  impl_ = learned_backend().new_model(network, electrodes, seed);
}

LearnedModel::LearnedModel(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
LearnedModel::~LearnedModel() = default;
LearnedModel::LearnedModel(LearnedModel&&) noexcept = default;
LearnedModel& LearnedModel::operator=(LearnedModel&&) noexcept = default;
LearnedModel::LearnedModel(const LearnedModel& other) : impl_(other.impl_->clone()) {}

LearnedModel& LearnedModel::operator=(const LearnedModel& other) {
  if (this != &other) impl_ = other.impl_->clone();
  return *this;
}

MeasurementProtocol LearnedModel::protocol() const {
  return impl_->info.protocol ? *impl_->info.protocol : adjacent_protocol(impl_->info.electrodes);
}

const ModelInfo& LearnedModel::info() const {
  return impl_->info;
}
ModelInfo& LearnedModel::info() {
  return impl_->info;
}

long long LearnedModel::parameters() const {
  return impl_->parameters();
}
std::vector<bool> LearnedModel::image_mask() const {
  return impl_->image_mask();
}
void LearnedModel::to_device(const std::string& device) {
  impl_->to_device(device);
}
std::string LearnedModel::device() const {
  return impl_->device();
}

SampleMatrix LearnedModel::reconstruct(const SampleMatrix& frames, int batch) const {
  return impl_->reconstruct(frames, batch);
}

Eigen::VectorXd LearnedModel::reconstruct(const Eigen::VectorXd& frame) const {
  const SampleMatrix one = frame.transpose();
  return impl_->reconstruct(one, 1).row(0).transpose();
}

std::string LearnedModel::to_bytes() const {
  return impl_->to_bytes();
}

LearnedModel LearnedModel::from_bytes(const std::string& bytes, const std::string& source) {
  return LearnedModel(learned_backend().read_model(bytes, source));
}

}  // namespace eitbench
