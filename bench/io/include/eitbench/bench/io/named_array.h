#pragma once
// Numeric arrays read from foreign files (NumPy, MATLAB), before they become frames.
#include <cstdint>
#include <string>
#include <vector>

namespace eitbench::detail {

struct NamedArray {
  std::string name;
  std::vector<std::size_t> shape;  // as the file's tool reports it (MATLAB: rows, columns)
  std::vector<double> values;      // row-major over `shape` (converted from column-major)
  bool numeric = true;             // false: a struct, cell, text, ... (values empty)
  std::string kind;                // what it is, for messages ("double", "struct", ...)
};

}  // namespace eitbench::detail
