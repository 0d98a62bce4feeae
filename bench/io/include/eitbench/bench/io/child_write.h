#pragma once
// Internal: writing an HDF5 file in a child process.
//
// Debian 12's libhdf5 (1.10.8) does not recover from a failed write. On a full disk `simulate`
// printed its message, and then the library, closing the half-written file again in its exit
// handler, crashed (exit 139). So every HDF5 file is written by a forked child: a one-shot writer
// inherits the data copy-on-write, a streaming one is sent its blocks over a socket. When a write
// fails, the child reports and leaves, and this process, which never held the file, throws an
// InputError: exit 2 and the message, never a crash. The caller writes to a temporary and renames
// it only after success (atomic_file.h), so nothing partial is left.
#include <functional>
#include <string>

namespace eitbench::detail {

// Runs `write` in a child and waits. An InputError there is thrown here again; a crash or another
// exception becomes an InputError naming `path`. Where no child can be made, `write` runs here.
void write_in_child(const std::string& path, const std::function<void()>& write);

// A child that holds a file open for a writer that streams: `open` runs in it at once, `apply`
// for each message sent, `close` on finish(). A failure in the child is reported by the next
// send() or by finish(), as write_in_child does.
class ChildWriter {
 public:
  ChildWriter(std::string path, std::function<void()> open,
              std::function<void(const std::string&)> apply, std::function<void()> close);
  ~ChildWriter();  // without finish(): the child stops and abandons the file
  ChildWriter(const ChildWriter&) = delete;
  ChildWriter& operator=(const ChildWriter&) = delete;

  void send(const std::string& message);
  void finish();

 private:
  void end_child();          // waits for the child's report: throws its error, if any
  [[noreturn]] void fail();  // the child stopped early: throws its report
  std::string path_;
  int fd_ = -1;
  int pid_ = -1;
};

}  // namespace eitbench::detail
