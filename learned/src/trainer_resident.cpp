// The trainer's resident path: the training set on the device (resident_set.h), and the rows of
// an epoch's batches in its layout.
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "eitbench/jacobian/error.h"
#include "trainer_impl.h"

namespace eitbench {

bool TrainerState::choose_residency() const {
  if (options.resident == "off" || (options.resident == "auto" && device.is_cpu())) return false;
  const long long samples = options.expanded ? train_size / group_size : train_size;
  const double need = ResidentSet::bytes(samples, group_size, train->frames.cols(),
                                         validation_labels.cols()),
               gib = std::pow(2.0, 30);
  if (need <= options.resident_max_gib * gib) return true;
  if (options.resident == "auto") return false;  // the host path gives the same batches
  char text[160];
  std::snprintf(text, sizeof text,
                "the resident training set needs %.2f GiB, more than %.2f: raise it, or set "
                "resident to off or auto",
                need / gib, options.resident_max_gib);
  throw InputError("TrainingOptions", "resident_max_gib", text);
}

// CUDA graphs replay the resident path's steps: they need a GPU, the set on it, and a build whose
// LibTorch has CUDA (validate() has refused "on" without the first two).
bool TrainerState::choose_graphs() const {
  if (options.cuda_graphs == "off" || !device.is_cuda()) return false;
  if (resident && cuda::compiled()) return true;
  if (options.cuda_graphs == "auto") return false;
  throw InputError("TrainingOptions", "cuda_graphs",
                   resident ? "this build's LibTorch has no CUDA graphs"
                            : "CUDA graphs need the resident training set, which did not fit in "
                              "resident_max_gib: raise it, or set cuda_graphs to auto or off");
}

// Every sample under every element, in expand_by_group's layout: from the expanded set (freed
// afterwards: the device holds it now), or through the augmenter, which gives the on-the-fly
// path's labels (the stored label for the identity).
void TrainerState::make_resident() {
  const long long samples = train->frames.rows(), pixels = validation_labels.cols();
  const auto& elements = augmenter ? augmenter->elements() : std::vector<GroupElement>{};
  auto source = [&](long long first, long long count, SampleMatrix& frames, SampleMatrix& labels) {
    const long long g = group_size;
    if (options.expanded) {
      frames = expanded.frames.middleRows(first * g, count * g);
      labels = expanded.labels.middleRows(first * g, count * g);
      return;
    }
    frames.resize(count * g, train->frames.cols());
    labels.resize(count * g, pixels);
    // Each row depends on its sample alone: parallel, and the same for any thread count.
    tbb::parallel_for(0LL, count, [&](long long i) {
      for (long long e = 0; e < g; ++e) {
        const int sample = static_cast<int>(first + i);
        frames.row(i * g + e) = augmenter->frame(sample, elements[e]).transpose();
        labels.row(i * g + e) = augmenter->label(sample, elements[e]).transpose();
      }
    });
  };
  resident = std::make_unique<ResidentSet>(samples, group_size, train->frames.cols(), pixels,
                                           source, device);
  if (options.expanded) expanded = LabelledFrames{};
}

torch::Tensor TrainerState::resident_rows(int epoch, const std::vector<long long>& order) const {
  if (options.expanded) return resident->upload(order);
  std::vector<long long> rows(order.size());
  const GroupElement* first = augmenter->elements().data();
  for (std::size_t k = 0; k < order.size(); ++k) {
    const int sample = static_cast<int>(order[k]);
    rows[k] = order[k] * group_size + (&augmenter->element(sample, epoch) - first);
  }
  return resident->upload(rows);
}

}  // namespace eitbench
