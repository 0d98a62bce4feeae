#pragma once
// What a benchmark run tells its reader: report.md (the paper's Table I for every method, the
// augmentation's relative improvement, runtime, training, data efficiency, figures), the choice of
// a reconstructor with its reasons, and the summary table on the terminal.
#include <string>
#include <vector>

#include "eitbench/bench/report/results.h"

namespace eitbench {

// Which method to use and why: the best CC at 40 dB (or the data's SNR), and the fastest method
// within 0.02 of it. Learned models whose training the budget ended before early stopping did are
// named as not converged: their figures may understate them.
std::string recommend(const std::vector<ResultRow>& rows);
// The SNR the pick and the touch ranking are made at: 40 dB when the rows have it, else the
// highest (noise-free, or measured frames' own). NaN without rows.
double headline_snr(const std::vector<ResultRow>& rows);
std::string recommend(const std::vector<ResultRow>& rows,
                      const std::vector<TrainingSummary>& training);
void write_report(const std::string& path, const RunResults& results);
std::string summary_table(const RunResults& results);

}  // namespace eitbench
