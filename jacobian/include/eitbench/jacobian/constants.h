#pragma once
// Mathematical constants (C++17 has no <numbers>).

namespace eitbench {

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace eitbench
