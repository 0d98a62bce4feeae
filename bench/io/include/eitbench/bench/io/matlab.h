#pragma once
// MATLAB .mat files: level 5 (compressed or not) parsed here, v7.3 through HDF5 in a child process;
// and level-5 files written (KTC2023's submissions are one).
#include <cstdint>
#include <string>
#include <vector>

#include "eitbench/bench/io/named_array.h"

namespace eitbench::detail {

std::vector<NamedArray> read_mat_v5(const std::string& bytes, const std::string& source);
std::vector<NamedArray> read_mat_v73(const std::string& path);

// A matrix to write: `values` row-major, rows x cols, stored as double or as uint8 (whole values
// 0 ... 255, as KTC's reconstructions are).
struct MatMatrix {
  std::string name;  // a MATLAB name: a letter, then letters, digits or _, at most 63
  std::size_t rows = 0, cols = 0;
  std::vector<double> values;
  bool uint8 = false;
};
// The bytes of a level-5 MAT file (uncompressed) holding `matrices`, as MATLAB's save -v6 and
// scipy.io.savemat write them. std::invalid_argument for a bad name, a size that does not match,
// or a uint8 value that is not a whole number in 0 ... 255.
std::string mat_v5_bytes(const std::vector<MatMatrix>& matrices);

}  // namespace eitbench::detail
