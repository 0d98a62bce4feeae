#pragma once
// A finished run's folder as the report reads it. The store is two files:
//   results.json         every figure, the configuration, the program and the machine
//   reconstructions.npy  float32 (rows, samples, n, n): the first test frames' images, noise-free;
//                        row 0 the truth (when the frames have labels), then one row for each
//                        method in results.json's order (a method, or dnn with an augmentation)
//   image_mask.npy       float32 (n, n), 1 inside the sensor: a sensor of another shape only (the
//                        disk's mask follows from n)
// Everything else in the folder is drawn from those two: report.md, results.csv,
// reconstructions.png, loss_curves.csv/.png and data_efficiency.png.
#include <string>
#include <vector>

#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/report/results.h"
#include "eitbench/jacobian/pixel_grid.h"

namespace eitbench {

// Writes the store into `folder` (atomically, file by file). `figure` holds the rows of
// reconstructions.npy in the order above, each with the same number of n x n images.
void write_run_store(const std::string& folder, const RunResults& results,
                     const std::vector<ImageRow>& figure, const PixelGrid& grid);

// Draws the report and its figures from the store in `folder` and returns the stored results,
// the recommendation made again from their rows by this version's rule.
// InputError naming the file on a missing or malformed store; a run without reconstructions.npy
// (an older version's) gets everything but reconstructions.png.
RunResults draw_run_report(const std::string& folder, bool quiet = true);

}  // namespace eitbench
