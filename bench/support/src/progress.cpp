#include "eitbench/bench/support/progress.h"

#include <fmt/core.h>
#include <unistd.h>

namespace eitbench {

Progress::Progress(std::string label, int total, bool quiet)
    : label_(std::move(label)),
      total_(total),
      quiet_(quiet),
      terminal_(::isatty(STDERR_FILENO) == 1) {
  start_ = last_draw_ = std::chrono::steady_clock::now();
}

void Progress::update(int done, const std::string& detail) {
  if (quiet_ || total_ <= 0) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  const double seconds = std::chrono::duration<double>(now - start_).count();
  const double rate = seconds > 0 ? done / seconds : 0;
  const double eta = rate > 0 ? (total_ - done) / rate : 0;
  if (terminal_) {
    if (done < total_ && now - last_draw_ < std::chrono::milliseconds(200)) return;
    last_draw_ = now;
    const int width = 30, filled = static_cast<int>(static_cast<long long>(width) * done / total_);
    fmt::print(stderr, "\r{} [{}{}] {:3d}% {}/{} {:.0f}/s, {:.0f} s left{}{}   ", label_,
               std::string(filled, '='), std::string(width - filled, ' '),
               static_cast<int>(100LL * done / total_), done, total_, rate, eta,
               detail.empty() ? "" : ", ", detail);
    if (done >= total_) fmt::print(stderr, "\n");
  } else {
    const int decile = static_cast<int>(10LL * done / total_);
    if (decile <= last_decile_) return;
    last_decile_ = decile;
    fmt::print(stderr, "{}: {:3d}% ({}/{}, {:.0f}/s, {:.0f} s left{}{})\n", label_, decile * 10,
               done, total_, rate, eta, detail.empty() ? "" : ", ", detail);
  }
}

void Progress::note(const std::string& line) {
  if (quiet_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  // On a terminal: clear the bar's line, print, and let the next update redraw the bar.
  fmt::print(stderr, "{}{}\n", terminal_ ? "\r\033[K" : "", line);
  last_draw_ = std::chrono::steady_clock::time_point{};
}

void Progress::finish() {
  update(total_);
}

}  // namespace eitbench
