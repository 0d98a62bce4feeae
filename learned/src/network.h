#pragma once
// The LibTorch side of learned/ (internal): the network module and conversions between Eigen's
// row-major sample matrices and tensors.
#include <torch/torch.h>

#include <string>

#include "eitbench/jacobian/sample_matrix.h"
#include "eitbench/learned/learned_model.h"
#include "eitbench/learned/network_options.h"

namespace eitbench {

// frames [B, inputs] (raw difference voltages) -> images [B, n^2], zero outside the disk. The input
// normalisation (mean, scale) and the disk mask are buffers: saved with the weights, moved with
// them to the device.
struct NetworkImpl : torch::nn::Module {
  explicit NetworkImpl(const NetworkOptions& options);
  torch::Tensor forward(const torch::Tensor& frames);

  NetworkOptions options;
  torch::nn::Sequential encoder{nullptr}, decoder{nullptr};
  torch::Tensor mean, scale, mask;
};
TORCH_MODULE(Network);

// A copy of `from`'s parameters and buffers into `to` (same shape).
void copy_state(const Network& from, Network& to);

// Row-major samples <-> float32 tensors.
torch::Tensor to_tensor(const SampleMatrix& rows, const torch::Device& device);
SampleMatrix to_samples(const torch::Tensor& tensor);

// LibTorch's message without its backtrace, first line only: what a user's error message quotes.
std::string first_line(const c10::Error& error);
// The first line of any other exception a damaged archive raises: TorchScript's parser reports a
// corrupted module's code as torch::jit::ErrorReport, a std::exception, not a c10::Error.
std::string first_line(const std::exception& error);

// The JSON of NetworkOptions, and back (InputError(source) on a missing or wrong field).
std::string network_to_json(const NetworkOptions& options);
NetworkOptions network_from_json(const std::string& json, const std::string& source);

}  // namespace eitbench
