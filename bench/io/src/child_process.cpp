#include "child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/core.h>

#include <cerrno>
#include <cstdio>

#include "eitbench/bench/io/sanitizers.h"
#include "eitbench/jacobian/error.h"

namespace eitbench::detail {

bool write_all(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

[[noreturn]] void run_as_child(int fd, const std::function<std::string()>& work) {
  // The child's death is the parent's to report. A fuzzer's or test driver's crash hooks, copied
  // by fork, would file libhdf5's crash as their own finding.
  ::signal(SIGABRT, SIG_DFL);
#ifdef EITBENCH_SANITIZED
  __sanitizer_set_death_callback(nullptr);
#endif
  int code = 0;
  std::string report;
  try {
    report = '0' + work();
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

namespace {

// libhdf5's C++ objects print their own failures to stderr as they are destroyed ("H5File::~H5File
// - H5Fclose failed"): a writing child reports through its pipe, which would only repeat it.
void quiet_stderr() {
  const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (null >= 0) ::dup2(null, STDERR_FILENO), ::close(null);
}

}  // namespace

int fork_child(int fds[2], const std::function<std::string()>& work, bool quiet) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int error = errno;  // the caller may name it
    ::close(fds[0]), ::close(fds[1]);
    errno = error;
    return -1;
  }
  if (pid == 0) {
    ::close(fds[0]);
    if (quiet) quiet_stderr();
    run_as_child(fds[1], work);
  }
  ::close(fds[1]);
  return pid;
}

int wait_for(int pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

std::string report_result(const std::string& path, std::string report, int status,
                          const std::string& doing) {
  if (WIFSIGNALED(status))
    throw InputError(
        path, "",
        fmt::format("the HDF5 library crashed {} (signal {}){}", doing, WTERMSIG(status),
                    doing == "reading the file" ? "; the file is corrupt" : ""));
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
    throw InputError(path, "",
                     std::string(doing == "reading the file" ? "cannot read the file: "
                                                             : "cannot write the file: ") +
                         report.substr(1));
  throw InputError(path, "",
                   fmt::format("the HDF5 library failed {} (exit status {}){}", doing, code,
                               doing == "reading the file" ? "; the file is corrupt" : ""));
}

}  // namespace eitbench::detail
