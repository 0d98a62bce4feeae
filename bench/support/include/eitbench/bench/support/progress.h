#pragma once
// A progress line for long work on stderr: a bar redrawn in place on a terminal, a line every 10 %
// otherwise (logs, CI). Safe to call from several threads.
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace eitbench {

class Progress {
 public:
  Progress(std::string label, int total, bool quiet = false);
  void update(int done, const std::string& detail = "");  // done of total; detail: "loss 0.01"
  // A line of its own (e.g. an epoch's summary), not overwritten by the bar.
  void note(const std::string& line);
  void finish();

 private:
  std::string label_;
  int total_;
  bool quiet_, terminal_;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_, last_draw_;
  std::mutex mutex_;
};

}  // namespace eitbench
