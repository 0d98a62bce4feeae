#include "eitbench/bench/io/child_read.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/core.h>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "child_process.h"
#include "eitbench/jacobian/error.h"

namespace eitbench::detail {
namespace {

double g_base_limit = 20;

}  // namespace

double child_read_limit(const std::string& path) {
  // The bytes the file occupies on disk, not its apparent size: a sparse file may claim
  // terabytes. And never more than kMaxExtra seconds on top, whatever the file says.
  constexpr double kMaxExtra = 120;
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return g_base_limit;
  const double stored = std::min(static_cast<double>(st.st_size), 512.0 * st.st_blocks);
  return g_base_limit + std::min(kMaxExtra, stored / 5e6);
}

void set_child_read_base_limit(double seconds) {
  g_base_limit = seconds;
}

std::string read_in_child(const std::string& path, const std::function<std::string()>& read) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return read();
  const int pid = fork_child(fds, read, false);
  if (pid < 0) return read();

  const double limit = child_read_limit(path);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit);
  std::string report;
  bool timed_out = false;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1000)));
    if (ready < 0 && errno != EINTR) break;
    if (ready <= 0) continue;
    char buffer[1 << 16];
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the child closed its end: it is leaving
    report.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  if (timed_out) ::kill(pid, SIGKILL);
  const int status = wait_for(pid);

  if (timed_out)
    throw InputError(path, "",
                     fmt::format("the HDF5 library did not finish reading the file in {:.0f} s; "
                                 "the file is corrupt",
                                 limit));
  return report_result(path, std::move(report), status, "reading the file");
}

}  // namespace eitbench::detail
