#include "resident_set.h"

#include <algorithm>

#include "network.h"

namespace eitbench {

double ResidentSet::bytes(long long samples, int group_size, long long inputs, long long pixels) {
  return 4.0 * double(samples) * double(group_size) * double(inputs + pixels);
}

ResidentSet::ResidentSet(long long samples, int group_size, long long inputs, long long pixels,
                         const RowSource& source, const torch::Device& device)
    : device_(device) {
  const auto options = torch::TensorOptions().dtype(torch::kFloat32).device(device);
  frames_ = torch::empty({samples * group_size, inputs}, options);
  labels_ = torch::empty({samples * group_size, pixels}, options);
  constexpr long long kChunk = 256;  // samples: |G| kChunk rows of host memory at a time
  SampleMatrix frames, labels;
  for (long long first = 0; first < samples; first += kChunk) {
    const long long count = std::min(kChunk, samples - first);
    source(first, count, frames, labels);
    const long long row = first * group_size, rows = count * group_size;
    frames_.narrow(0, row, rows).copy_(to_tensor(frames, torch::kCPU));
    labels_.narrow(0, row, rows).copy_(to_tensor(labels, torch::kCPU));
  }
}

torch::Tensor ResidentSet::upload(const std::vector<long long>& rows) const {
  const auto host = torch::from_blob(const_cast<long long*>(rows.data()),
                                     {static_cast<long long>(rows.size())}, torch::kInt64);
  return device_.is_cpu() ? host.clone() : host.to(device_);  // `rows` may go out of scope
}

std::pair<torch::Tensor, torch::Tensor> ResidentSet::batch(const torch::Tensor& rows,
                                                           long long start, long long end) const {
  return gather(rows.narrow(0, start, end - start));
}

std::pair<torch::Tensor, torch::Tensor> ResidentSet::gather(const torch::Tensor& rows) const {
  return {frames_.index_select(0, rows), labels_.index_select(0, rows)};
}

}  // namespace eitbench
