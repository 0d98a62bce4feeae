// Three planted bugs, so that the smoke job is shown to find each kind of finding it exists to find
// (the FuzzSmoke.finds_* tests). PLANTED_BUG picks one; the seeds are clean, and only mutants
// (inputs shorter than the 10-byte seed) trip it.
//  - throws: an input shorter than 4 bytes throws an exception that is not InputError.
//  - hangs: an input shorter than 3 bytes never returns.
//  - overflows: byte 0 declares how many bytes follow, and the target sums that many without
//    checking: a truncated mutant reads past its buffer, which AddressSanitizer reports.
//  - bloats: byte 0 declares a size in 4 MiB blocks, which the target allocates and fills without
//    a budget: a mutant with a large byte 0 takes the peak memory past --rss-limit-mb.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string bug = std::getenv("PLANTED_BUG") ? std::getenv("PLANTED_BUG") : "";
  if (size == 0) return 0;
  if (bug == "throws") {
    if (size < 4) throw std::runtime_error("planted: a short input");
    return 0;
  }
  if (bug == "hangs") {
    for (volatile bool forever = size < 3; forever;) {
    }
    return 0;
  }
  if (bug == "bloats") {
    std::vector<std::vector<char>> blocks(data[0]);  // planted: trusts the declared size
    for (auto& block : blocks) block.assign(std::size_t(4) << 20, static_cast<char>(size));
    return blocks.empty() ? 0 : blocks.back()[0];
  }
  const std::vector<std::uint8_t> copy(data, data + size);  // on the heap, where ASan watches
  unsigned sum = 0;
  for (std::size_t i = 1; i <= copy[0]; ++i) sum += copy[i];  // planted: trusts the declared size
  return sum == 0xffffffffu ? 1 : 0;
}
