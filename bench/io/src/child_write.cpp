#include "eitbench/bench/io/child_write.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>

#include "child_process.h"
#include "eitbench/jacobian/error.h"

namespace eitbench::detail {
namespace {

// Reads until the other end closes: the child's report.
std::string read_to_end(int fd) {
  std::string report;
  char buffer[1 << 14];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return report;
    report.append(buffer, static_cast<std::size_t>(n));
  }
}

bool read_exactly(int fd, char* out, std::size_t size) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::read(fd, out + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// send() that cannot raise SIGPIPE when the child is gone: false instead.
bool send_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n, size -= static_cast<std::size_t>(n);
  }
  return true;
}

// A message on the socket: its kind ('m' a message, 'c' close), its length, its bytes.
bool send_message(int fd, char kind, const std::string& bytes) {
  char head[9];
  head[0] = kind;
  const std::uint64_t size = bytes.size();
  std::memcpy(head + 1, &size, sizeof size);
  return send_all(fd, head, sizeof head) && send_all(fd, bytes.data(), bytes.size());
}

// The child's loop: messages until 'c' (close, report success) or the parent's end closing
// (abandoned: leave quietly, the parent removes the temporary).
std::string serve(int fd, const std::function<void(const std::string&)>& apply,
                  const std::function<void()>& close) {
  for (;;) {
    char head[9];
    if (!read_exactly(fd, head, sizeof head)) ::_exit(0);
    std::uint64_t size = 0;
    std::memcpy(&size, head + 1, sizeof size);
    if (head[0] == 'c') {
      close();
      return "";
    }
    std::string message(size, '\0');
    if (!read_exactly(fd, message.data(), size)) ::_exit(0);
    apply(message);
  }
}

}  // namespace

void write_in_child(const std::string& path, const std::function<void()>& write) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return write();
  const int pid = fork_child(
      fds,
      [&] {
        write();
        return std::string();
      },
      true);
  if (pid < 0) return write();
  std::string report = read_to_end(fds[0]);
  ::close(fds[0]);
  report_result(path, std::move(report), wait_for(pid), "writing the file");
}

ChildWriter::ChildWriter(std::string path, std::function<void()> open,
                         std::function<void(const std::string&)> apply, std::function<void()> close)
    : path_(std::move(path)) {
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
    throw InputError(path_, "", "cannot start the writer: " + std::string(std::strerror(errno)));
  const int pid = fork_child(
      fds,
      [&] {
        open();
        return serve(fds[1], apply, close);
      },
      true);
  if (pid < 0)
    throw InputError(path_, "", "cannot start the writer: " + std::string(std::strerror(errno)));
  fd_ = fds[0], pid_ = pid;
}

ChildWriter::~ChildWriter() {
  if (pid_ < 0) return;
  ::close(fd_);  // the child sees the end and leaves
  wait_for(pid_);
}

void ChildWriter::send(const std::string& message) {
  if (pid_ < 0) throw std::logic_error("ChildWriter::send after finish");
  pollfd p{fd_, POLLIN, 0};  // a report before the end is a failure: say it now
  if (::poll(&p, 1, 0) > 0 || !send_message(fd_, 'm', message)) fail();
}

void ChildWriter::finish() {
  if (pid_ < 0) throw std::logic_error("ChildWriter::finish twice");
  if (!send_message(fd_, 'c', "")) fail();
  end_child();
}

void ChildWriter::end_child() {
  ::shutdown(fd_, SHUT_WR);
  std::string report = read_to_end(fd_);
  ::close(fd_);
  const int status = wait_for(pid_);
  pid_ = -1;
  report_result(path_, std::move(report), status, "writing the file");
}

void ChildWriter::fail() {
  end_child();  // throws the child's error
  throw InputError(path_, "", "the writer stopped before the file was complete");
}

}  // namespace eitbench::detail
