#pragma once
// NumPy's .npy (one array) and .npz (a ZIP archive of them, stored or deflated, zip64 too).
#include <string>
#include <vector>

#include "eitbench/bench/io/named_array.h"
#include "eitbench/jacobian/read_budget.h"

namespace eitbench::detail {

// Parse the file's bytes; InputError naming `source` and the field on anything malformed, and on
// sizes past the memory rule of eitbench/jacobian/read_budget.h (an .npz's members share one
// budget; their directory must give each member bytes and a name of its own).
NamedArray read_npy(const std::string& bytes, const std::string& source, const std::string& name);
NamedArray read_npy(const std::string& bytes, const std::string& source, const std::string& name,
                    ReadBudget& budget);
std::vector<NamedArray> read_npz(const std::string& bytes, const std::string& source);

// A float32 array of `shape` (C order) as .npy bytes; values.size() must equal the shape's product.
std::string npy_bytes(const std::vector<float>& values, const std::vector<std::size_t>& shape);

}  // namespace eitbench::detail
