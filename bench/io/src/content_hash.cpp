#include "eitbench/bench/io/content_hash.h"

#include <fmt/core.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "eitbench/jacobian/random.h"

namespace eitbench {

void Hasher::add(std::uint64_t bits) {
  h_ = mix64(h_ ^ bits);
}

void Hasher::add(double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  add(bits);
}

void Hasher::add(const std::string& text) {
  add(static_cast<std::uint64_t>(text.size()));
  std::uint64_t word = 0;
  for (std::size_t k = 0; k < text.size(); ++k) {
    word = (word << 8) | static_cast<unsigned char>(text[k]);
    if (k % 8 == 7) add(word), word = 0;
  }
  add(word);
}

std::string Hasher::hex() const {
  return fmt::format("{:016x}", h_);
}

std::string file_hash(const std::string& path) {
  if (path.empty()) return "";
  std::ifstream in(path, std::ios::binary);
  Hasher h;
  h.add(std::string(std::istreambuf_iterator<char>(in), {}));
  return h.hex();
}

}  // namespace eitbench
