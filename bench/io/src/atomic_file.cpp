#include "eitbench/bench/io/atomic_file.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <random>
#include <sstream>

#include "eitbench/bench/io/output_path.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/input_file.h"
#include "eitbench/jacobian/read_budget.h"

namespace eitbench {
namespace fs = std::filesystem;

namespace {

// False when `pid` is gone, or a zombie that nobody reaped (as in containers without an init).
bool process_alive(pid_t pid) {
  if (::kill(pid, 0) != 0 && errno == ESRCH) return false;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  std::getline(stat, text);
  const auto close = text.rfind(')');
  return !(close != std::string::npos && close + 2 < text.size() && text[close + 2] == 'Z');
}

}  // namespace

std::string temporary_path_for(const std::string& path) {
  const fs::path target(output_target(path));
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  if (!fs::is_directory(dir))
    throw InputError(path, "", "the folder " + dir.string() + " does not exist");
  // A process killed while writing (SIGKILL cannot be caught) leaves its temporary behind: the
  // next writer of the same target removes those whose process is gone.
  const std::string prefix = "." + target.stem().string() + ".tmp",
                    suffix = target.extension().string();
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string digits =
        name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::strtol(digits.c_str(), nullptr, 10);
    if (pid > 0 && pid != ::getpid() && !process_alive(static_cast<pid_t>(pid)))
      fs::remove(entry.path(), error);
  }
  return (dir / (prefix + std::to_string(::getpid()) + suffix)).string();
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string&)>& write) {
  const fs::path target(output_target(path));
  const fs::path temp = temporary_path_for(path);
  try {
    write(temp.string());
  } catch (...) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw;
  }
  std::error_code error;
  fs::rename(temp, target, error);
  if (error) {
    fs::remove(temp, error);
    throw InputError(path, "", "cannot write the file: " + error.message());
  }
}

void write_text_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
  write_atomically(path, [&](const std::string& temp) {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out)
      throw InputError(path, "", "cannot create the file: " + std::string(std::strerror(errno)));
    write(out);
    out.close();  // a full disk may show only here, when the last buffer is written
    if (!out) throw InputError(path, "", "writing failed (disk full?)");
  });
}

std::string read_file_bytes(const std::string& path, long long max_bytes) {
  require_input_file(path);
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  if (error) throw InputError(path, "", "cannot read the file: " + error.message());
  if (size == 0) throw InputError(path, "", "the file is empty");
  if (max_bytes < 0) max_bytes = static_cast<long long>(read_limit_bytes());
  if (static_cast<long long>(size) > max_bytes)
    throw InputError(path, "",
                     "the file is " + byte_size_text(static_cast<double>(size)) +
                         ", more than the " + byte_size_text(static_cast<double>(max_bytes)) +
                         " allowed" +
                         (max_bytes == static_cast<long long>(read_limit_bytes())
                              ? " (EITBENCH_READ_LIMIT raises it)"
                              : ""));
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

}  // namespace eitbench
