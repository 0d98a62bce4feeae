#pragma once
// Internal: numeric arrays from the foreign files import reads (CSV, NumPy, MATLAB), and the one
// a command's --variable names.
#include <functional>
#include <string>
#include <vector>

#include "eitbench/bench/io/named_array.h"

namespace eitbench::detail {

// The file's extension in lower case (".mat").
std::string lower_extension(const std::string& path);

// The arrays of a file by its extension, and how it was read (`format`, and whether its tool
// stores columns first). A CSV's rows are `fits` widths a line, or columns of at most `longest`
// lines. InputError for a missing file or an unknown type.
std::vector<NamedArray> read_arrays(const std::string& path,
                                    const std::function<bool(std::size_t)>& fits,
                                    std::size_t longest, std::string& format, bool& columns_first);

// The array named `variable`, or (none named) the only numeric one, or the first of
// `preferred` present; InputError naming the file's arrays otherwise.
const NamedArray& choose(const std::vector<NamedArray>& arrays, const std::string& variable,
                         const std::string& path,
                         const std::vector<std::string>& preferred = {"frames", "data", "vv", "v",
                                                                      "voltages", "meas"});

}  // namespace eitbench::detail
