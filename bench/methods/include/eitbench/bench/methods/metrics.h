#pragma once
// Image quality against the label (docs/conventions.md), over the in-disk pixels, on the label
// scale.
#include <Eigen/Core>
#include <vector>

#include "eitbench/jacobian/pixel_grid.h"
#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench {

struct ImageScores {
  double cc = 0;   // Pearson correlation (0 when either image is constant)
  double re = 0;   // ||x_hat - x|| / ||x|| (infinite for an all-zero label)
  double mse = 0;  // mean squared error
  double ssim =
      0;  // structural similarity: 11x11 Gaussian window, sigma 1.5, C1 = 0.01^2, C2 = 0.03^2
};

ImageScores score_image(const Eigen::VectorXd& image, const Eigen::VectorXd& label,
                        const PixelGrid& grid);

struct ScoreSummary {
  ImageScores mean, std;
  int count = 0;
};
// Row i of `images` against row i of `labels`; per-image scores in `each` when given.
ScoreSummary score_images(const SampleMatrix& images, const SampleMatrix& labels,
                          const PixelGrid& grid, std::vector<ImageScores>* each = nullptr);

double correlation(const Eigen::VectorXd& image, const Eigen::VectorXd& label,
                   const PixelGrid& grid);

}  // namespace eitbench
