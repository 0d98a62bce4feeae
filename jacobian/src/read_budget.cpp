#include "eitbench/jacobian/read_budget.h"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

constexpr std::uint64_t kDefaultLimit = std::uint64_t(2) << 30;
constexpr double kUncheckedOutput = 64 * 1024;  // tiny arrays: no ratio to speak of
std::atomic<std::uint64_t> g_limit{0};

std::uint64_t parse_limit(const char* text) {
  const std::string source = "EITBENCH_READ_LIMIT";
  char* end = nullptr;
  const double number = std::strtod(text, &end);
  std::string unit(end);
  while (!unit.empty() && unit.front() == ' ') unit.erase(0, 1);
  const double scale = unit.empty() || unit == "B"    ? 1
                       : unit == "KiB" || unit == "K" ? 1024.0
                       : unit == "MiB" || unit == "M" ? 1024.0 * 1024
                       : unit == "GiB" || unit == "G" ? 1024.0 * 1024 * 1024
                                                      : -1;
  if (end == text || !std::isfinite(number) || number <= 0 || scale < 0)
    throw InputError(
        source, "",
        std::string("'") + text + "' is not a size (bytes, or a number with KiB, MiB or GiB)");
  if (number * scale < 1024 * 1024 || number * scale > 1e15)
    throw InputError(source, "", std::string("'") + text + "' is outside 1 MiB .. 1 PB");
  return static_cast<std::uint64_t>(number * scale);
}

}  // namespace

std::uint64_t read_limit_bytes() {
  std::uint64_t limit = g_limit.load();
  if (limit == 0) {
    const char* text = std::getenv("EITBENCH_READ_LIMIT");
    limit = text && *text ? parse_limit(text) : kDefaultLimit;
    g_limit.store(limit);
  }
  return limit;
}

void set_read_limit_bytes(std::uint64_t bytes) {
  g_limit.store(bytes);
}

std::string byte_size_text(double bytes) {
  char text[64];
  const double gib = 1024.0 * 1024 * 1024, mib = 1024.0 * 1024;
  if (bytes >= gib)
    std::snprintf(text, sizeof text, "%.1f GiB", bytes / gib);
  else if (bytes >= mib)
    std::snprintf(text, sizeof text, "%.1f MiB", bytes / mib);
  else
    std::snprintf(text, sizeof text, "%.0f bytes", bytes);
  return text;
}

ReadBudget::ReadBudget(std::string source)
    : source_(std::move(source)), limit_(static_cast<double>(read_limit_bytes())) {}

double ReadBudget::left() const {
  return limit_ > used_ ? limit_ - used_ : 0;
}

void ReadBudget::take(const std::string& field, double bytes, const std::string& declared) {
  if (!(bytes >= 0) || used_ + bytes > limit_)
    throw InputError(source_, field,
                     "declares " + (declared.empty() ? "" : declared + ", ") +
                         byte_size_text(bytes) + " in memory" +
                         (used_ > 0 ? " (" + byte_size_text(used_) + " before it)" : "") +
                         ", more than the " + byte_size_text(limit_) +
                         " one file may decode into (EITBENCH_READ_LIMIT raises it)");
  used_ += bytes;
}

void ReadBudget::take_compressed(const std::string& field, double decoded, double stored,
                                 double in_memory, const std::string& declared) {
  if (decoded > kUncheckedOutput && decoded > kMaxInflation * stored)
    throw InputError(source_, field,
                     "declares " + (declared.empty() ? "" : declared + ", ") +
                         byte_size_text(decoded) + " stored in " + byte_size_text(stored) +
                         ", more than the " + std::to_string(static_cast<int>(kMaxInflation)) +
                         "-fold that compression can give: the sizes are false, or the data "
                         "were never written");
  take(field, in_memory, declared);
}

}  // namespace eitbench
