#pragma once
// The data-efficiency sweep as a reader sees it (the paper's Fig. 8): CC and RE against the
// training-set size on a log axis, the table, and the headline: the fewest frames with which D16
// matches what no augmentation reaches with the most.
#include <ostream>
#include <string>
#include <vector>

#include "eitbench/bench/report/results.h"

namespace eitbench {

// "D16 reaches no augmentation's CC at n = N (0.xyz) with n = M frames, K x fewer", or why not.
std::string efficiency_headline(const std::vector<EfficiencyPoint>& points);
// report.md's section: the headline, the table, the figures.
void write_efficiency_section(std::ostream& out, const std::vector<EfficiencyPoint>& points);
// data_efficiency.png (CC) and data_efficiency_re.png (RE) in `folder`, drawn by gnuplot with
// their data and scripts beside them (gnuplot.h); false when gnuplot is missing (data and scripts
// only).
bool draw_efficiency_figures(const std::vector<EfficiencyPoint>& points, const std::string& folder);

}  // namespace eitbench
