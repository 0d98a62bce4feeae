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

void check_model_protocol(const LearnedModel& model, const std::string& path,
                          const MeasurementProtocol& protocol) {
  const MeasurementProtocol trained = model.protocol();
  if (trained.same_channels(protocol)) return;
  auto describe = [](const MeasurementProtocol& p) {
    return p.name() + (p.magnitude() ? " (magnitudes)" : "") + ", " + std::to_string(p.size()) +
           " channels, " + std::to_string(p.input_size()) + " inputs";
  };
  throw InputError(path, "protocol",
                   "the model was trained on the " + describe(trained) +
                       "; the data are read on the " + describe(protocol) +
                       ": train a model on this protocol");
}

void check_model_fits(const LearnedModel& model, const std::string& path, int electrodes,
                      const PixelGrid& grid) {
  check_model_fits(model, path, electrodes, grid.size());
  const std::vector<bool> drawn = model.image_mask();
  int differ = 0;
  for (Eigen::Index p = 0; p < grid.mask().size(); ++p)
    differ += drawn[static_cast<std::size_t>(p)] != grid.mask()[p];
  if (differ > 0)
    throw InputError(path, "mask",
                     "the model draws another sensor's shape: " + std::to_string(differ) +
                         " of its pixels differ from the data's sensor (" +
                         std::to_string(grid.num_inside()) + " inside); train it on this sensor");
}

}  // namespace eitbench
