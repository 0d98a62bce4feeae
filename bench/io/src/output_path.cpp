#include "eitbench/bench/io/output_path.h"

#include <filesystem>
#include <mutex>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace fs = std::filesystem;

namespace {

std::mutex g_mutex;
std::vector<std::string> g_inputs;

}  // namespace

void declare_inputs(const std::vector<std::string>& paths) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  for (const std::string& path : paths) {
    std::error_code error;
    if (!path.empty() && fs::is_regular_file(path, error)) g_inputs.push_back(path);
  }
}

std::string output_target(const std::string& path) {
  if (path.empty()) throw InputError("--out", "", "the output path is empty");
  std::error_code error;
  fs::path target(path);
  if (fs::is_symlink(fs::symlink_status(target, error))) {
    // Most users who point a link somewhere mean the file there: it is replaced, the link kept.
    target = fs::canonical(target, error);
    if (error)
      throw InputError(path, "",
                       "is a symbolic link to nothing (" + error.message() +
                           "): remove it, or point it at a file");
  }
  const fs::file_status status = fs::status(target, error);
  if (!fs::exists(status)) return target.string();
  if (fs::is_directory(status)) throw InputError(path, "", "is a directory, expected a file name");
  if (!fs::is_regular_file(status))
    throw InputError(path, "",
                     "is a FIFO, a device or a socket: eitbench writes only regular files");
  const std::lock_guard<std::mutex> lock(g_mutex);
  for (const std::string& input : g_inputs)
    if (fs::equivalent(target, input, error))
      throw InputError(path, "",
                       "is the same file as the input " + input +
                           ": writing it would destroy the input; choose another output");
  return target.string();
}

}  // namespace eitbench
