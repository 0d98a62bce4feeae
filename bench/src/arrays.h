#pragma once
// Internal: numeric arrays read from foreign files (NumPy, MATLAB), before they become frames.
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


NamedArray read_npy(const std::string& bytes, const std::string& source, const std::string& name);
std::vector<NamedArray> read_npz(const std::string& bytes, const std::string& source);
std::vector<NamedArray> read_mat_v5(const std::string& bytes, const std::string& source);
std::vector<NamedArray> read_mat_v73(const std::string& path);

// Inflates zlib (raw = false) or raw deflate (raw = true) data, refusing output beyond `limit`.
std::string inflate(const char* data, std::size_t size, bool raw, std::size_t limit,
                    const std::string& source, const std::string& field);

}  // namespace eitbench::detail
