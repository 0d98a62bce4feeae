#pragma once
// A small, platform-independent random stream (splitmix64). The standard library's distributions
// are implementation-defined; these are not, so a seed gives the same data on every machine.
#include <cmath>
#include <cstdint>

namespace eitbench {

inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

class RandomStream {
 public:
  // An independent stream for each (seed, stream) pair, e.g. (data-set seed, sample index).
  RandomStream(std::uint64_t seed, std::uint64_t stream)
      : state_(mix64(mix64(seed) ^ mix64(stream + 0x632be59bd9b4e019ULL))) {}

  std::uint64_t next() { return mix64(state_ += 0x9e3779b97f4a7c15ULL); }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  double normal() {  // Box-Muller; 1 - u keeps the logarithm finite
    const double u = 1.0 - uniform(), v = uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * M_PI * v);
  }

 private:
  std::uint64_t state_;
};

}  // namespace eitbench
