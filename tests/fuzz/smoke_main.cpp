// A deterministic stand-in for libFuzzer's driver, so that every fuzz target also runs in the
// ordinary test suite, built by gcc, with no clang (issue 8's CI-sized smoke job). It feeds the
// target each seed and then a fixed number of mutants of the seeds: bit flips, interesting bytes
// and integers, numbers in text replaced by extreme ones, erased, inserted and duplicated ranges,
// truncations and splices — libFuzzer's mutations without its coverage feedback. The same
// --seed gives the same inputs. A finding is an exception other than InputError escaping the
// target (std::bad_alloc among them), a fatal signal (with the sanitizers, any report), one input
// running past --timeout, or the process's peak memory passing --rss-limit-mb (libFuzzer's
// -rss_limit_mb: a small input that makes a parser allocate gigabytes); the input is written to
// the findings folder and the exit status is 1.
//
// usage: fuzz_smoke_TARGET [--runs N] [--seed S] [--timeout SECONDS] [--rss-limit-mb MB]
//                          [--findings DIR] SEED_FILE_OR_FOLDER...
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "eitbench/bench/io/sanitizers.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;
using Bytes = std::string;

// The input being run and where a fatal signal writes it; plain globals because the signal handler
// may use only async-signal-safe calls.
const Bytes* g_current = nullptr;
char g_crash_path[4096] = "";

void write_current_input() {
  if (g_current == nullptr || g_crash_path[0] == '\0') return;
  const int fd = ::open(g_crash_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return;
  std::size_t done = 0;
  while (done < g_current->size()) {
    const ssize_t n = ::write(fd, g_current->data() + done, g_current->size() - done);
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  ::close(fd);
}

void on_fatal_signal(int signal) {
  write_current_input();
  const char message[] = "\nfuzz smoke: fatal signal; the input is in the findings folder\n";
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, message, sizeof message - 1);
  ::signal(signal, SIG_DFL);
  ::raise(signal);
}

void on_timeout(int) {
  write_current_input();
  const char message[] =
      "\nfuzz smoke: an input ran past --timeout (a hang); it is in the findings folder\n";
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, message, sizeof message - 1);
  ::_exit(1);
}

[[noreturn]] void usage_error(const std::string& what) {
  std::fprintf(stderr,
               "fuzz smoke: %s\nusage: fuzz_smoke_TARGET [--runs N] [--seed S] [--timeout SECONDS] "
               "[--rss-limit-mb MB] [--findings DIR] SEED_FILE_OR_FOLDER...\n",
               what.c_str());
  std::exit(2);
}

long parse_count(const std::string& flag, const char* text) {
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || value < 0) usage_error(flag + " needs a non-negative integer");
  return value;
}

Bytes read_seed(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) usage_error("cannot read seed " + path.string());
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Seeds in a fixed order (sorted paths), whatever order the file system lists them in.
std::vector<Bytes> load_seeds(const std::vector<std::string>& args) {
  std::vector<fs::path> paths;
  for (const auto& arg : args) {
    if (fs::is_directory(arg)) {
      for (const auto& entry : fs::directory_iterator(arg))
        if (entry.is_regular_file()) paths.push_back(entry.path());
    } else if (fs::is_regular_file(arg)) {
      paths.emplace_back(arg);
    } else {
      usage_error("no such seed file or folder: " + arg);
    }
  }
  std::sort(paths.begin(), paths.end());
  std::vector<Bytes> seeds;
  for (const auto& path : paths) seeds.push_back(read_seed(path));
  if (seeds.empty()) seeds.emplace_back();  // the empty input still seeds the mutations
  return seeds;
}

class Mutator {
 public:
  Mutator(std::uint64_t seed, const std::vector<Bytes>& seeds) : random_(seed), seeds_(seeds) {
    for (const auto& s : seeds) max_size_ = std::max(max_size_, 2 * s.size() + 64);
  }

  // One to five stacked mutations of a seed drawn at random.
  Bytes next() {
    Bytes input = seeds_[below(seeds_.size())];
    const std::size_t depth = 1 + below(5);
    for (std::size_t i = 0; i < depth; ++i) mutate(input);
    if (input.size() > max_size_) input.resize(max_size_);
    return input;
  }

 private:
  std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(random_() % n); }

  void mutate(Bytes& s) {
    switch (below(9)) {
      case 0:  // flip one bit
        if (!s.empty()) s[below(s.size())] ^= static_cast<char>(1u << below(8));
        break;
      case 1: {  // one byte to an interesting or random value
        static constexpr std::array<unsigned char, 16> kBytes = {
            0, 1, 0x7f, 0x80, 0xff, '0', '9', '-', '.', 'e', '\n', ',', ' ', '"', '{', 0xfe};
        if (!s.empty())
          s[below(s.size())] =
              static_cast<char>(below(2) ? kBytes[below(kBytes.size())] : below(256));
        break;
      }
      case 2: {  // an integer of 1, 2, 4 or 8 bytes (binary headers) to an extreme value
        static constexpr std::array<std::uint64_t, 8> kValues = {
            0, 1, 0xff, 0x7fffffff, 0x80000000, 0xffffffff, 0x7fffffffffffffff, ~0ull};
        const std::size_t width = std::size_t{1} << below(4);
        if (s.size() < width) break;
        const std::uint64_t v = kValues[below(kValues.size())];
        std::memcpy(&s[below(s.size() - width + 1)], &v, width);  // little-endian here
        break;
      }
      case 3: {  // a number in text to an extreme one
        static const std::array<const char*, 12> kNumbers = {
            "0",   "-1",  "-0",    "2147483648", "4294967296", "18446744073709551616",
            "nan", "inf", "1e308", "-1e308",     "1e-320",     "99999999999999999999999"};
        const std::size_t from = below(s.size() + 1);
        auto is_digit = [](char c) { return c >= '0' && c <= '9'; };
        const auto begin =
            std::find_if(s.begin() + static_cast<std::ptrdiff_t>(from), s.end(), is_digit);
        if (begin == s.end()) break;
        const auto end = std::find_if_not(begin, s.end(), is_digit);
        s.replace(begin, end, kNumbers[below(kNumbers.size())]);
        break;
      }
      case 4:  // erase a range
        if (!s.empty()) {
          const std::size_t at = below(s.size());
          s.erase(at, 1 + below(std::min<std::size_t>(s.size() - at, below(2) ? 16 : s.size())));
        }
        break;
      case 5: {  // insert random bytes
        Bytes bytes(1 + below(16), '\0');
        for (auto& b : bytes) b = static_cast<char>(below(256));
        s.insert(below(s.size() + 1), bytes);
        break;
      }
      case 6:  // duplicate a range
        if (!s.empty()) {
          const std::size_t at = below(s.size());
          const Bytes part = s.substr(at, 1 + below(std::min<std::size_t>(s.size() - at, 256)));
          s.insert(below(s.size() + 1), part);
        }
        break;
      case 7:  // truncate
        s.resize(below(s.size() + 1));
        break;
      default: {  // splice: this input's head and another seed's tail
        const Bytes& other = seeds_[below(seeds_.size())];
        s = s.substr(0, below(s.size() + 1)) + other.substr(below(other.size() + 1));
        break;
      }
    }
  }

  std::mt19937_64 random_;
  const std::vector<Bytes>& seeds_;
  std::size_t max_size_ = 64;
};

}  // namespace

int main(int argc, char** argv) {
  long runs = 10000, seed = 1, timeout = 10, rss_limit_mb = 2048;
  fs::path findings = ".";
  std::vector<std::string> seed_args;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) usage_error(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--runs")
      runs = parse_count(arg, value());
    else if (arg == "--seed")
      seed = parse_count(arg, value());
    else if (arg == "--timeout")
      timeout = std::max(1L, parse_count(arg, value()));
    else if (arg == "--rss-limit-mb")
      rss_limit_mb = std::max(1L, parse_count(arg, value()));
    else if (arg == "--findings")
      findings = value();
    else if (arg.rfind("--", 0) == 0)
      usage_error("unknown option " + arg);
    else
      seed_args.push_back(arg);
  }
  const std::string target = fs::path(argv[0]).filename().string();
  const std::vector<Bytes> seeds = load_seeds(seed_args);
  fs::create_directories(findings);
  const std::string crash_path = (findings / ("finding-" + target)).string();
  std::snprintf(g_crash_path, sizeof g_crash_path, "%s", crash_path.c_str());
#ifdef EITBENCH_SANITIZED
  // The sanitizers report memory errors and undefined behaviour themselves, then exit; the input
  // is saved on the way out.
  __sanitizer_set_death_callback(write_current_input);
  ::signal(SIGABRT, on_fatal_signal);
#else
  for (int s : {SIGSEGV, SIGABRT, SIGFPE, SIGBUS, SIGILL}) ::signal(s, on_fatal_signal);
#endif
  ::signal(SIGALRM, on_timeout);

  Mutator mutator(static_cast<std::uint64_t>(seed), seeds);
  long executions = 0, findings_count = 0;
  // The first few escaping exceptions are saved and named; the rest are only counted.
  auto report_exception = [&](long k, const Bytes& input, const char* what) {
    if (++findings_count > 10) return;
    const std::string path = crash_path + "-" + std::to_string(k);
    std::ofstream(path, std::ios::binary) << input;
    std::fprintf(stderr, "fuzz smoke: input %ld threw %s (not InputError); saved as %s\n", k, what,
                 path.c_str());
  };
  const auto start = std::chrono::steady_clock::now();
  const long total = static_cast<long>(seeds.size()) + runs;
  for (long k = 0; k < total; ++k) {
    const Bytes input = k < static_cast<long>(seeds.size()) ? seeds[k] : mutator.next();
    g_current = &input;
    ::alarm(static_cast<unsigned>(timeout));
    try {
      LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
    } catch (const std::exception& e) {
      report_exception(k, input, e.what());
    } catch (...) {
      report_exception(k, input, "a non-standard exception");
    }
    ::alarm(0);
    g_current = nullptr;
    ++executions;
    // The peak only grows: the first input to pass the limit is the finding, and the run ends.
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    if (usage.ru_maxrss / 1024 > rss_limit_mb) {
      const std::string path = crash_path + "-" + std::to_string(k);
      std::ofstream(path, std::ios::binary) << input;
      std::fprintf(stderr,
                   "fuzz smoke: input %ld took peak memory to %ld MB, past --rss-limit-mb %ld; "
                   "saved as %s\n",
                   k, usage.ru_maxrss / 1024, rss_limit_mb, path.c_str());
      ++findings_count;
      break;
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "%s: %ld executions (%zu seeds, %ld mutants, seed %ld) in %.1f s, %.0f exec/s, "
      "%ld findings\n",
      target.c_str(), executions, seeds.size(), runs, seed, seconds,
      executions / std::max(seconds, 1e-9), findings_count);
  return findings_count == 0 ? 0 : 1;
}
