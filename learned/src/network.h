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
  // The decoder in channels-last (NHWC) memory, or back in the standard NCHW: its convolution
  // weights are laid out again (values unchanged) and its activations follow. cuDNN's tensor-core
  // convolutions work in NHWC and transpose NCHW tensors to it and back; in NHWC they need not.
  // Set before an optimiser's state is made: Adam's moments take their parameters' layout.
  void use_channels_last(bool on);
  bool channels_last() const { return channels_last_; }

  NetworkOptions options;
  torch::nn::Sequential encoder{nullptr}, decoder{nullptr};
  torch::Tensor mean, scale, mask;

 private:
  bool channels_last_ = false;
};
TORCH_MODULE(Network);

// torch::pixel_shuffle that keeps a channels-last input's layout: the output is channels-last
// too. LibTorch's own returns NCHW on a GPU (its CPU kernel keeps the layout), so the next
// convolution would transpose it back. Any other input goes to torch::pixel_shuffle.
torch::Tensor pixel_shuffle_keeping_layout(const torch::Tensor& x, int factor);

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
