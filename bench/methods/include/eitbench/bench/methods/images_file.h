#pragma once
// Reconstructions as an HDF5 file: /images (N x n x n float32, label scale), /frame_index (N),
// /scores (N x 4: cc, re, mse, ssim) when labels were known; attributes method, settings, data,
// mesh, background, setup_s, latency_median_ms, latency_p95_ms, program; and for a method that
// finds circles (shape), /circles (N x 4 x [x, y, r, sigma], NaN-padded) and /circle_count (N)
// in the data set's layout.
#include <map>
#include <string>
#include <vector>

#include "eitbench/bench/methods/metrics.h"
#include "eitbench/jacobian/geometry.h"
#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench {

struct ImagesFile {
  SampleMatrix images;
  std::vector<int> frame_index;
  std::vector<ImageScores> scores;           // empty without labels
  std::vector<std::vector<Circle>> circles;  // empty unless the method finds circles
  std::map<std::string, std::string> text;
  std::map<std::string, double> numbers;
};

void write_images_file(const std::string& path, const ImagesFile& content);  // atomic

}  // namespace eitbench
