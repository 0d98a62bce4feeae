#pragma once
// KTC2023's score of a reconstruction (docs/ktc.md#the-score), computed from its published
// definition: the mean of the structural similarity (SSIM) of the conductive masks and of the
// resistive masks. SSIM here is the challenge's: a Gaussian window of standard deviation 80 px cut
// at 160 px, every local mean and moment divided by the window's coverage of the image (zero
// padding outside), c1 = 1e-4, c2 = 9e-4, averaged over every pixel.
#include <Eigen/Core>
#include <cstdint>

namespace eitbench {

// Classes on KTC's grid: 0 water, 1 resistive, 2 conductive; row 0 at the top.
using ClassImage = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr int kKtcImageSize = 256;  // KTC's grid: 256 x 256 pixels over the 230 mm square

// The challenge's SSIM of two images of the same size (masks of 0 and 1 in the score; any values
// here). std::invalid_argument for images of different sizes or an empty one.
double ktc_ssim(const Eigen::MatrixXd& truth, const Eigen::MatrixXd& reconstruction);

struct KtcScore {
  double conductive = 0;  // SSIM of the class-2 masks
  double resistive = 0;   // SSIM of the class-1 masks
  double total() const { return 0.5 * (conductive + resistive); }
};

// The score of `reconstruction` against `truth`. InputError("truth", "size") when the truth is
// not 256 x 256; a reconstruction of another size scores 0, as the challenge scored it.
KtcScore ktc_score(const ClassImage& truth, const ClassImage& reconstruction);

// The same for many reconstructions against one truth: the truth's windowed moments are computed
// once (what a threshold sweep needs). Equal to ktc_score, value for value.
class KtcScorer {
 public:
  explicit KtcScorer(const ClassImage& truth);
  KtcScore operator()(const ClassImage& reconstruction) const;
  // The SSIM of the truth's class `cls` (1 or 2) against `mask` (256 x 256, 0 and 1): one half of
  // the score, for rules that set the two classes apart (std::invalid_argument otherwise).
  double ssim(int cls, const Eigen::MatrixXd& mask) const;

 private:
  struct Moments {
    Eigen::MatrixXd mean, second;  // windowed mean and mean of squares
  };
  Eigen::MatrixXd truth_[2];  // class 2 and class 1 masks
  Moments moments_[2];
};

}  // namespace eitbench
