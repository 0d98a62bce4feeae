#pragma once
// Losses as JSON (internal to learned/): an infinite loss (none yet) is written as null.
#include <limits>
#include <nlohmann/json.hpp>

namespace eitbench {

constexpr double kNoLoss = std::numeric_limits<double>::infinity();

nlohmann::json finite_or_null(double v);
double number_or_infinity(const nlohmann::json& j);

}  // namespace eitbench
