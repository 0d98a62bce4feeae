#pragma once
// Internal: one function run in a forked child, and its report to the parent (child_read.h,
// child_write.h). The report is a kind byte and what follows: '0' and the function's bytes; '2'
// and an InputError's source, field and message separated by NULs; '3' and another exception's
// what().
#include <functional>
#include <string>

namespace eitbench::detail {

// Writes all of `bytes` to `fd` (false when the other end is gone).
bool write_all(int fd, const std::string& bytes);

// In the child: runs `work`, sends its report to `fd`, and leaves with status 0, 2 or 3 without
// running the parent's exit handlers (libhdf5's among them: its state is the child's loss).
[[noreturn]] void run_as_child(int fd, const std::function<std::string()>& work);

// Forks a child that runs `work` through run_as_child, reporting on fds[1] (a pipe or a socket
// pair, both close-on-exec), with its stderr silenced when `quiet`. Flushes stdio first, so that
// nothing buffered is written twice. Returns the child's pid with fds[1] closed here, or -1 with
// both closed (and errno kept) when no process could be made.
int fork_child(int fds[2], const std::function<std::string()>& work, bool quiet);

// The child's wait status, waited for through EINTR.
int wait_for(int pid);

// In the parent, from a report and the child's wait status: the bytes of a report '0', or the
// InputError the child threw, thrown again here; a crash or anything else becomes an InputError
// naming `path` that says the library `doing` ("reading the file", "writing the file") failed.
std::string report_result(const std::string& path, std::string report, int status,
                          const std::string& doing);

}  // namespace eitbench::detail
