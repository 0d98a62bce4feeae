#pragma once
namespace eitbench {
const char* program_version();  // "eitbench 0.1.0"
}  // namespace eitbench
