#include "eitbench/jacobian/input_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "eitbench/jacobian/error.h"

namespace eitbench {

namespace fs = std::filesystem;

void require_input_file(const std::string& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (status.type() == fs::file_type::not_found) throw InputError(path, "", "no such file");
  if (error) throw InputError(path, "", "cannot be read: " + error.message());
  if (fs::is_directory(status)) throw InputError(path, "", "is a folder, not a file");
  if (!fs::is_regular_file(status))
    throw InputError(path, "", "is not a regular file (a FIFO, a device or a socket)");
  if (::access(path.c_str(), R_OK) != 0)
    throw InputError(path, "", "cannot be read: " + std::string(std::strerror(errno)));
}

void require_input_folder(const std::string& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (status.type() == fs::file_type::not_found) throw InputError(path, "", "no such folder");
  if (error) throw InputError(path, "", "cannot be read: " + error.message());
  if (!fs::is_directory(status)) throw InputError(path, "", "is a file, not a folder");
}

}  // namespace eitbench
