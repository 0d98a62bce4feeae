#pragma once
// A 64-bit hash of values and of a file's bytes, written as 16 hex digits: what a run's stage
// records of its inputs (provenance) and what a sensor file records of the presses it was fitted
// on, so that two files with the same bytes are known to be the same wherever they lie.
#include <Eigen/Core>
#include <cstdint>
#include <string>

namespace eitbench {

class Hasher {
 public:
  void add(std::uint64_t bits);
  void add(double v);
  void add(const std::string& text);
  template <typename Matrix>
  void add_matrix(const Matrix& m) {
    add(static_cast<std::uint64_t>(m.rows())), add(static_cast<std::uint64_t>(m.cols()));
    for (Eigen::Index k = 0; k < m.size(); ++k) add(static_cast<double>(m.data()[k]));
  }
  std::string hex() const;

 private:
  std::uint64_t h_ = 0x9e3779b97f4a7c15ull;
};

// Of a file's bytes ("" for an empty path; a file that cannot be read hashes as empty).
std::string file_hash(const std::string& path);

}  // namespace eitbench
