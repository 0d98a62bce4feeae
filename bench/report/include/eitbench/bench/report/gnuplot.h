#pragma once
// Line plots drawn by gnuplot (Debian's gnuplot-nox: the pngcairo and svg terminals). Beside each
// figure X.png the writer leaves X.dat (the data, one block per series) and X.gp (the script that
// draws X.png and X.svg from X.dat), so a user can restyle a figure and draw it again with
// `gnuplot X.gp` in its folder. Without gnuplot the data and the script are still written.
#include <string>

#include "eitbench/bench/report/figures.h"

namespace eitbench {

// The gnuplot to run: EITBENCH_GNUPLOT, or `gnuplot` on the PATH; "" when there is none.
std::string gnuplot_program();

// Writes X.dat and X.gp for `png_path` (X.png), then draws X.png and X.svg with gnuplot when it is
// there; every file appears whole or not at all. True when the figure was drawn. A gnuplot that
// fails is an InputError naming the figure and gnuplot's message.
bool write_plot(const LinePlot& plot, const std::string& png_path);

// The colour of a series in every figure, by its key: each method has its own (the learned
// reconstructor one per augmentation, "dnn (d16)"), others take the next of a fixed palette.
std::string series_colour(const std::string& key);

}  // namespace eitbench
