#pragma once
// The training set resident on the training device (internal to learned/): every sample under
// every group element as float32 rows, sample-major (row i |G| + k is sample i under element k,
// expand_by_group's layout), so a batch is one index gather on the device and a step never waits
// for the host. The rows are the host path's rows converted once, so the batches are the same.
#include <torch/torch.h>

#include <functional>
#include <utility>
#include <vector>

#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench {

class ResidentSet {
 public:
  // Fills `frames` and `labels` (resized) with samples first .. first + count - 1 under every
  // element: count |G| rows in the layout above.
  using RowSource = std::function<void(long long first, long long count, SampleMatrix& frames,
                                       SampleMatrix& labels)>;

  // Device memory the set takes: samples |G| (inputs + pixels) float32 values.
  static double bytes(long long samples, int group_size, long long inputs, long long pixels);

  // Copies the rows over in chunks of a few hundred samples (host memory stays small).
  ResidentSet(long long samples, int group_size, long long inputs, long long pixels,
              const RowSource& source, const torch::Device& device);

  // Row indices (into the layout above) as an int64 tensor on the device: uploaded once an epoch.
  torch::Tensor upload(const std::vector<long long>& rows) const;
  // Frames and labels of rows[start, end), gathered on the device.
  std::pair<torch::Tensor, torch::Tensor> batch(const torch::Tensor& rows, long long start,
                                                long long end) const;
  // Frames and labels of every row in `rows` (int64, on the device).
  std::pair<torch::Tensor, torch::Tensor> gather(const torch::Tensor& rows) const;

 private:
  torch::Device device_;
  torch::Tensor frames_, labels_;
};

}  // namespace eitbench
