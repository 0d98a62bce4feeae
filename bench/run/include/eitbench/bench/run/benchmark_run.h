#pragma once
// The benchmark run: data, every model-based method with its hyperparameter chosen on validation
// data, the learned reconstructor trained without and with augmentation, every method scored on
// the test split noise-free and at 50, 40 and 30 dB, the data-efficiency sweep; then the results
// store (results.json, reconstructions.npy) and the report drawn from it. docs/ARCHITECTURE.md
// draws the stages.
#include "eitbench/bench/report/results.h"
#include "eitbench/bench/run/config.h"

namespace eitbench {

// Runs every stage (reusing finished ones with config.resume), writes into config.out, and returns
// the figures.
RunResults run_benchmark(const RunConfig& config);

}  // namespace eitbench
