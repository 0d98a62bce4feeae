#pragma once
// The touch metrics as a reader sees them (docs/benchmark.md#touch-metrics): report.md's table at
// one SNR with the best method by centre error, by count accuracy and by CC, count accuracy and
// centre error at every SNR, and the figure of the centre errors by method.
#include <ostream>
#include <string>
#include <vector>

#include "eitbench/bench/report/results.h"

namespace eitbench {

// Whether any row was scored for touches (false for measured frames and older results).
bool has_touch_scores(const std::vector<ResultRow>& rows);
// "Best centre error: ...; best count accuracy: ...; best CC: ..." at `snr`, naming every method
// tied for the best; empty without touch scores there.
std::string touch_ranking(const std::vector<ResultRow>& rows, double snr);
// report.md's section; nothing without touch scores.
void write_touch_section(std::ostream& out, const std::vector<ResultRow>& rows, double snr);
// touch_centre_errors.png: for each method at `snr`, the share of true touches found within a
// centre distance, against that distance (x R), from the stored quantiles; drawn by gnuplot with
// its data and script beside it (gnuplot.h), false when gnuplot is missing.
bool draw_touch_figure(const std::vector<ResultRow>& rows, double snr, const std::string& path);

}  // namespace eitbench
