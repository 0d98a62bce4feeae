#pragma once
// Real presses as a reader sees them (docs/real-presses.md): report.md's section ranking every
// method by where it puts the presses of the measured set beside its simulated touch error, the
// fine-tuning table and its headline, and the figure of error against labelled presses.
#include <ostream>
#include <string>
#include <vector>

#include "eitbench/bench/report/results.h"

namespace eitbench {

// report.md's section; nothing when the run scored no real presses.
void write_press_section(std::ostream& out, const RunResults& results);
// press_finetune.png: mean centre error against the labelled presses a model was trained or
// fine-tuned on (log scale), one line per way of training, beside the methods that need no
// labelled presses as flat lines. Drawn by gnuplot (gnuplot.h); false when it is missing.
bool draw_press_figure(const RunResults& results, const std::string& path);
// The headline of the fine-tuning: the fewest presses with d16 augmentation whose fine-tuned mean
// error is at most the best plain (unaugmented) mean at any size; empty without fine-tuning.
std::string finetune_headline(const std::vector<MeasuredRow>& rows, double unit_mm);

}  // namespace eitbench
