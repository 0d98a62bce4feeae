#pragma once
// MATLAB .mat files: level 5 (compressed or not) parsed here, v7.3 through HDF5 in a child process.
#include <string>
#include <vector>

#include "eitbench/bench/io/named_array.h"

namespace eitbench::detail {

std::vector<NamedArray> read_mat_v5(const std::string& bytes, const std::string& source);
std::vector<NamedArray> read_mat_v73(const std::string& path);

}  // namespace eitbench::detail
