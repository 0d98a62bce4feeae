#include "eitbench/bench/support/machine.h"

#include <filesystem>
#include <fstream>
#include <thread>

#include "eitbench/learned/runtime.h"

namespace eitbench {
namespace {

// The value after "key" and a separator on the first line of `path` that starts with it.
std::string field_of(const std::string& path, const std::string& key, char separator) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key, 0) == 0) {
      const auto at = line.find(separator);
      if (at == std::string::npos) continue;
      std::string v = line.substr(at + 1);
      v.erase(0, v.find_first_not_of(" \t\""));
      while (!v.empty() && (v.back() == '"' || v.back() == ' ')) v.pop_back();
      return v;
    }
  return "unknown";
}

}  // namespace

std::map<std::string, std::string> describe_machine() {
  std::map<std::string, std::string> m;
  m["cpu"] = field_of("/proc/cpuinfo", "model name", ':');
  m["cores"] = std::to_string(std::thread::hardware_concurrency());
  m["memory"] = field_of("/proc/meminfo", "MemTotal", ':');
  m["os"] = field_of("/etc/os-release", "PRETTY_NAME", '=');
  std::error_code error;
  const auto blas =
      std::filesystem::canonical("/usr/lib/x86_64-linux-gnu/libblas.so.3", error).string();
  m["blas"] = error ? "unknown" : blas;
  m["torch_threads"] = std::to_string(torch_threads());
  m["thread_layout"] = thread_layout().describe();
  m["gpu"] = cuda_available() ? "cuda" : "none";
  return m;
}

}  // namespace eitbench
