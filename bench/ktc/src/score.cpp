#include "eitbench/bench/ktc/score.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "eitbench/jacobian/error.h"
#include "eitbench/solvers/dense_lapack.h"

namespace eitbench {
namespace {

constexpr double kSigma = 80, kC1 = 1e-4, kC2 = 9e-4;
constexpr int kHalfWidth = 160;  // ceil(2 sigma)

// The window's 1-D kernel at offset d: a Gaussian cut at kHalfWidth. The same for rows and columns.
double kernel(Eigen::Index d) {
  const auto x = static_cast<double>(d);
  return std::abs(d) <= kHalfWidth ? std::exp(-0.5 * x * x / (kSigma * kSigma)) : 0.0;
}

// The window as an n x n band matrix G (G(i, k) = g(i - k)): conv2(X, g g^T, 'same') = G X G^T,
// zero outside the image. The kernel's constant factor cancels against the coverage.
Eigen::MatrixXd window(Eigen::Index n) {
  Eigen::MatrixXd G(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index k = 0; k < n; ++k) G(i, k) = kernel(i - k);
  return G;
}

// The kernel's prefix sums over offsets -(n - 1) ... n - 1: prefix[d + n] is the sum of g(e) for
// e <= d, so that a run of ones from a to b in a column of x gives (G x)(i) = prefix[i - a + n] -
// prefix[i - b + n - 1].
std::vector<double> prefix_sums(Eigen::Index n) {
  std::vector<double> p(static_cast<std::size_t>(2 * n), 0.0);
  for (Eigen::Index d = -(n - 1); d <= n - 1; ++d)
    p[static_cast<std::size_t>(d + n)] = p[static_cast<std::size_t>(d + n - 1)] + kernel(d);
  return p;
}

bool is_mask(const Eigen::MatrixXd& x) {
  for (Eigen::Index k = 0; k < x.size(); ++k)
    if (x.data()[k] != 0 && x.data()[k] != 1) return false;
  return true;
}

// Windowed means of a family of images of one size: the window's products and its coverage,
// computed once.
class Window {
 public:
  Window(Eigen::Index rows, Eigen::Index cols)
      : Gr_(window(rows)), GcT_(window(cols).transpose()), prefix_(prefix_sums(rows)) {
    coverage_ = detail::product(detail::product(Gr_, Eigen::MatrixXd::Ones(rows, cols)), GcT_);
  }
  // Through the system's BLAS (one thread): a threshold sweep scores each image at 40 masks, two
  // means a mask, and on 256 x 256 the products took a third of Eigen's time (2-core AMD EPYC).
  Eigen::MatrixXd mean(const Eigen::MatrixXd& x) const {
    if (is_mask(x)) return mask_mean(x);
    return detail::product(detail::product(Gr_, x), GcT_).cwiseQuotient(coverage_);
  }

 private:
  // A mask's mean (G_r x G_c^T) with one product instead of two, over its occupied columns only:
  // G_r x is the kernel's sum over each column's runs of ones, two prefix sums a run, and only the
  // occupied columns l reach the second factor, as rows l of G_c^T. A sweep's masks are runs of a
  // smooth image's thresholds, a few a column, and most leave most columns empty.
  Eigen::MatrixXd mask_mean(const Eigen::MatrixXd& x) const {
    const Eigen::Index n = x.rows();
    std::vector<Eigen::Index> occupied;
    for (Eigen::Index l = 0; l < x.cols(); ++l)
      if ((x.col(l).array() != 0).any()) occupied.push_back(l);
    if (occupied.empty()) return Eigen::MatrixXd::Zero(n, x.cols());
    const auto C = static_cast<Eigen::Index>(occupied.size());
    Eigen::MatrixXd left = Eigen::MatrixXd::Zero(n, C), right(C, x.cols());
    for (Eigen::Index c = 0; c < C; ++c) {
      const Eigen::Index l = occupied[static_cast<std::size_t>(c)];
      right.row(c) = GcT_.row(l);
      add_runs(x.col(l).data(), n, left.col(c).data());
    }
    return detail::product(left, right).cwiseQuotient(coverage_);
  }

  // Adds G_r's sum over each run of ones in `column` (n values) to `out`: two prefix sums a run,
  // over the rows the window reaches from it (beyond, the two are equal and the term is 0).
  void add_runs(const double* column, Eigen::Index n, double* out) const {
    Eigen::Index a = 0;
    while (a < n) {
      if (column[a] == 0) {
        ++a;
        continue;
      }
      Eigen::Index b = a;  // the run's last row
      while (b + 1 < n && column[b + 1] != 0) ++b;
      const Eigen::Index last = std::min(n - 1, b + kHalfWidth);
      for (Eigen::Index i = std::max<Eigen::Index>(0, a - kHalfWidth); i <= last; ++i)
        out[i] += prefix_[static_cast<std::size_t>(i - a + n)] -
                  prefix_[static_cast<std::size_t>(i - b + n - 1)];
      a = b + 1;
    }
  }

  Eigen::MatrixXd Gr_, GcT_, coverage_;
  std::vector<double> prefix_;  // the kernel's (prefix_sums), over G_r's offsets
};

const Window& window_for(Eigen::Index rows, Eigen::Index cols) {
  if (rows == kKtcImageSize && cols == kKtcImageSize) {
    static const Window ktc(kKtcImageSize, kKtcImageSize);
    return ktc;
  }
  thread_local Eigen::Index r = -1, c = -1;
  thread_local std::unique_ptr<Window> other;
  if (r != rows || c != cols) other = std::make_unique<Window>(rows, cols), r = rows, c = cols;
  return *other;
}

// SSIM averaged over the image, from both images' windowed moments and their cross moment.
double ssim_from(const Eigen::MatrixXd& mt, const Eigen::MatrixXd& st2, const Eigen::MatrixXd& mr,
                 const Eigen::MatrixXd& sr2, const Eigen::MatrixXd& mtr) {
  // One pass, no temporaries: a sweep computes it 40 times an image.
  double sum = 0;
  for (Eigen::Index i = 0; i < mt.size(); ++i) {
    const double mu_t = mt.data()[i], mu_r = mr.data()[i];
    const double var_t = st2.data()[i] - mu_t * mu_t, var_r = sr2.data()[i] - mu_r * mu_r;
    const double cov = mtr.data()[i] - mu_t * mu_r;
    sum += (2 * mu_t * mu_r + kC1) * (2 * cov + kC2) /
           ((mu_t * mu_t + mu_r * mu_r + kC1) * (var_t + var_r + kC2));
  }
  return sum / static_cast<double>(mt.size());
}

Eigen::MatrixXd mask(const ClassImage& image, int cls) {
  return (image.array() == static_cast<std::uint8_t>(cls)).cast<double>().matrix();
}

}  // namespace

double ktc_ssim(const Eigen::MatrixXd& truth, const Eigen::MatrixXd& reconstruction) {
  if (truth.size() == 0 || truth.rows() != reconstruction.rows() ||
      truth.cols() != reconstruction.cols())
    throw std::invalid_argument("ktc_ssim: two images of one size");
  const Window& w = window_for(truth.rows(), truth.cols());
  return ssim_from(w.mean(truth), w.mean(truth.cwiseProduct(truth)), w.mean(reconstruction),
                   w.mean(reconstruction.cwiseProduct(reconstruction)),
                   w.mean(truth.cwiseProduct(reconstruction)));
}

KtcScorer::KtcScorer(const ClassImage& truth) {
  if (truth.rows() != kKtcImageSize || truth.cols() != kKtcImageSize)
    throw InputError("truth", "size",
                     "is " + std::to_string(truth.rows()) + " x " + std::to_string(truth.cols()) +
                         "; KTC's ground truths are 256 x 256");
  const Window& w = window_for(kKtcImageSize, kKtcImageSize);
  for (int k = 0; k < 2; ++k) {
    truth_[k] = mask(truth, k == 0 ? 2 : 1);
    moments_[k].mean = w.mean(truth_[k]);
    moments_[k].second = moments_[k].mean;  // a mask is its own square
  }
}

double KtcScorer::ssim(int cls, const Eigen::MatrixXd& r) const {
  if ((cls != 1 && cls != 2) || r.rows() != kKtcImageSize || r.cols() != kKtcImageSize)
    throw std::invalid_argument("KtcScorer::ssim: class 1 or 2, a 256 x 256 mask");
  const int k = cls == 2 ? 0 : 1;
  const Window& w = window_for(kKtcImageSize, kKtcImageSize);
  const Eigen::MatrixXd mr = w.mean(r);  // a mask is its own square
  return ssim_from(moments_[k].mean, moments_[k].second, mr, mr, w.mean(truth_[k].cwiseProduct(r)));
}

KtcScore KtcScorer::operator()(const ClassImage& reconstruction) const {
  KtcScore s;
  if (reconstruction.rows() != kKtcImageSize || reconstruction.cols() != kKtcImageSize) return s;
  s.conductive = ssim(2, mask(reconstruction, 2));
  s.resistive = ssim(1, mask(reconstruction, 1));
  return s;
}

KtcScore ktc_score(const ClassImage& truth, const ClassImage& reconstruction) {
  return KtcScorer(truth)(reconstruction);
}

}  // namespace eitbench
