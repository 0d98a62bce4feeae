#pragma once
// LearnedModel on LibTorch (internal): the network, in evaluation mode, on its device.
#include <torch/torch.h>

#include "backend.h"
#include "network.h"

namespace eitbench {

struct TorchModel final : LearnedModel::Impl {
  TorchModel() = default;
  TorchModel(const NetworkOptions& network, int electrodes, std::uint64_t seed);
  static std::unique_ptr<TorchModel> from_bytes(const std::string& bytes,
                                                const std::string& source);

  std::unique_ptr<LearnedModel::Impl> clone() const override;
  long long parameters() const override;
  std::vector<bool> image_mask() const override;
  SampleMatrix reconstruct(const SampleMatrix& frames, int batch) const override;
  void to_device(const std::string& device) override;
  std::string device() const override;
  std::string to_bytes() const override;

  Network net{nullptr};
  torch::Device on = torch::kCPU;  // where net is
};

}  // namespace eitbench
