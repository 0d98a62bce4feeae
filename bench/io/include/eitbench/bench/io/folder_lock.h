#pragma once
// One writer per output folder. Two runs into one folder wrote its results.json and report.md in
// turn, and which run's rows ended up there was chance. A command that writes a folder takes an
// OS file lock (flock) on <folder>/.eitbench.lock for as long as it runs; the kernel releases it
// when the process ends, however it ends (SIGKILL included), so a stale lock cannot block.
#include <string>

namespace eitbench {

class FolderLock {
 public:
  // Takes the lock, or throws InputError(folder) naming the process that holds it.
  explicit FolderLock(const std::string& folder);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace eitbench
