#include "eitbench/bench/model_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "eitbench/bench/io.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

std::string read_file_bytes(const std::string& path, long long max_bytes) {
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  if (error) throw InputError(path, "", "cannot read the file: " + error.message());
  if (size == 0) throw InputError(path, "", "the file is empty");
  if (static_cast<long long>(size) > max_bytes)
    throw InputError(path, "",
                     "the file is " + std::to_string(size) + " bytes, more than the " +
                         std::to_string(max_bytes) + " allowed");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open the file: " + std::string(std::strerror(errno)));
  std::string bytes(size, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (in.gcount() != static_cast<std::streamsize>(size))
    throw InputError(path, "", "the file could not be read whole");
  return bytes;
}

void write_bytes_atomically(const std::string& path, const std::string& bytes) {
  write_text_atomically(path, [&](std::ostream& out) {
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

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
