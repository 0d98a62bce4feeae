#pragma once
// What a figure was measured on: CPU, cores, memory, operating system, BLAS, LibTorch's threads
// and whether a GPU was usable.
#include <map>
#include <string>

namespace eitbench {
std::map<std::string, std::string> describe_machine();
}  // namespace eitbench
