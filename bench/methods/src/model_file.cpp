#include "eitbench/bench/methods/model_file.h"

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

LearnedModel read_model_file(const std::string& path) {
  return LearnedModel::from_bytes(read_file_bytes(path), path);
}

void write_model_file(const std::string& path, const LearnedModel& model) {
  write_bytes_atomically(path, model.to_bytes());
}

void check_model_fits(const LearnedModel& model, const std::string& path, int electrodes,
                      int image_size) {
  const ModelInfo& info = model.info();
  if (info.electrodes != electrodes)
    throw InputError(path, "electrodes",
                     "the model was trained for " + std::to_string(info.electrodes) +
                         " electrodes, the data have " + std::to_string(electrodes));
  if (info.network.image_size != image_size)
    throw InputError(path, "image_size",
                     "the model draws " + std::to_string(info.network.image_size) +
                         " px images, the data's are " + std::to_string(image_size) + " px");
}

}  // namespace eitbench
