#include "eitbench/bench/io/child_read.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/core.h>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "eitbench/bench/io/sanitizers.h"
#include "eitbench/jacobian/error.h"

namespace eitbench::detail {
namespace {

double g_base_limit = 20;

void write_all(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

// In the child: run `read` and send its bytes after a kind byte ('0'; on an InputError '2' and its
// source, field and message separated by NULs; on another exception '3' and what()), then leave
// without running the parent's exit handlers.
[[noreturn]] void child(int fd, const std::function<std::string()>& read) {
  // The child's death is the parent's to report. A fuzzer's or test driver's crash hooks, copied
  // by fork, would file libhdf5's crash as their own finding.
  ::signal(SIGABRT, SIG_DFL);
#ifdef EITBENCH_SANITIZED
  __sanitizer_set_death_callback(nullptr);
#endif
  int code = 0;
  std::string report;
  try {
    report = '0' + read();
  } catch (const InputError& e) {
    code = 2, report = '2' + e.source() + '\0' + e.field() + '\0' + e.message();
  } catch (const std::exception& e) {
    code = 3, report = std::string("3") + e.what();
  } catch (...) {
    code = 3, report = "3an unknown error";
  }
  write_all(fd, report);
  ::close(fd);
  ::_exit(code);
}

}  // namespace

double child_read_limit(const std::string& path) {
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  return g_base_limit + (error ? 0.0 : static_cast<double>(size) / 5e6);
}

void set_child_read_base_limit(double seconds) {
  g_base_limit = seconds;
}

std::string read_in_child(const std::string& path, const std::function<std::string()>& read) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return read();
  std::fflush(nullptr);  // nothing buffered is written twice
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]), ::close(fds[1]);
    return read();
  }
  if (pid == 0) {
    ::close(fds[0]);
    child(fds[1], read);
  }
  ::close(fds[1]);

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
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }

  if (timed_out)
    throw InputError(path, "",
                     fmt::format("the HDF5 library did not finish reading the file in {:.0f} s; "
                                 "the file is corrupt",
                                 limit));
  if (WIFSIGNALED(status))
    throw InputError(path, "",
                     fmt::format("the HDF5 library crashed reading the file (signal {}); the "
                                 "file is corrupt",
                                 WTERMSIG(status)));
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  const char kind = report.empty() ? ' ' : report[0];
  if (code == 0 && kind == '0') {
    report.erase(0, 1);  // in place, and moved out: it may hold most of a large data set
    return report;
  }
  if (code == 2 && kind == '2') {
    const auto a = report.find('\0'), b = a == std::string::npos ? a : report.find('\0', a + 1);
    if (b != std::string::npos)
      throw InputError(report.substr(1, a - 1), report.substr(a + 1, b - a - 1),
                       report.substr(b + 1));
  }
  if (code == 3 && kind == '3')
    throw InputError(path, "", "cannot read the file: " + report.substr(1));
  throw InputError(path, "",
                   fmt::format("the HDF5 library failed reading the file (exit status {}); the "
                               "file is corrupt",
                               code));
}

}  // namespace eitbench::detail
