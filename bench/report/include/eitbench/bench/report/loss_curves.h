#pragma once
// Training curves: training and validation MSE against training samples seen (the paper's Fig. 6)
// for one run or several.
#include <string>
#include <utility>
#include <vector>

#include "eitbench/learned/trainer.h"

namespace eitbench {

// The loss curves of one run or several (label each), as CSV rows and a figure drawn by gnuplot
// (gnuplot.h; its .dat and .gp beside it). False when gnuplot is missing (CSV, data, script).
bool write_loss_curves(
    const std::string& csv_path, const std::string& png_path,
    const std::vector<std::pair<std::string, std::vector<TrainingRecord>>>& runs);

}  // namespace eitbench
