// KTC2023's score against its definition computed independently (windowed moments summed pixel by
// pixel), and the values it must take by construction; the segmentation rules, the resampling onto
// KTC's grid, and the submission file read back.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/matlab.h"
#include "eitbench/bench/ktc/ktc_files.h"
#include "eitbench/bench/ktc/score.h"
#include "eitbench/bench/ktc/segmentation.h"
#include "test_support.h"

namespace eitbench {
namespace {

// The challenge's SSIM by its definition, summed directly: the 321 x 321 Gaussian (sigma 80)
// around each pixel, every moment divided by the window's weight inside the image.
double brute_force_ssim(const Eigen::MatrixXd& t, const Eigen::MatrixXd& r) {
  const double c1 = 1e-4, c2 = 9e-4;
  double total = 0;
  for (Eigen::Index i = 0; i < t.rows(); ++i)
    for (Eigen::Index j = 0; j < t.cols(); ++j) {
      double w = 0, mt = 0, mr = 0, tt = 0, rr = 0, tr = 0;
      for (Eigen::Index k = 0; k < t.rows(); ++k)
        for (Eigen::Index l = 0; l < t.cols(); ++l) {
          const double di = double(i - k), dj = double(j - l);
          if (std::abs(di) > 160 || std::abs(dj) > 160) continue;
          const double g = std::exp(-0.5 * (di * di + dj * dj) / 6400.0);
          w += g, mt += g * t(k, l), mr += g * r(k, l);
          tt += g * t(k, l) * t(k, l), rr += g * r(k, l) * r(k, l), tr += g * t(k, l) * r(k, l);
        }
      mt /= w, mr /= w, tt /= w, rr /= w, tr /= w;
      const double num = (2 * mt * mr + c1) * (2 * (tr - mt * mr) + c2);
      const double den = (mt * mt + mr * mr + c1) * (tt - mt * mt + rr - mr * mr + c2);
      total += num / den;
    }
  return total / static_cast<double>(t.size());
}

ClassImage random_blobs(unsigned seed, int size = kKtcImageSize) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.2, 0.8);
  ClassImage img = ClassImage::Zero(size, size);
  for (int b = 0; b < 3; ++b) {
    const double ci = u(rng) * size, cj = u(rng) * size, radius = 0.15 * u(rng) * size;
    const std::uint8_t cls = static_cast<std::uint8_t>(1 + b % 2);
    for (int i = 0; i < size; ++i)
      for (int j = 0; j < size; ++j)
        if (std::hypot(i - ci, j - cj) < radius) img(i, j) = cls;
  }
  return img;
}

Eigen::MatrixXd as_double(const ClassImage& c, int cls) {
  return (c.array() == cls).cast<double>().matrix();
}

TEST(KtcScore, EqualsItsDefinitionSummedPixelByPixel) {
  // Images smaller than the window, so that the coverage correction matters everywhere; and one
  // of 256 x 256 rows at a few pixels is too slow by brute force, so two small sizes.
  for (int size : {24, 37}) {
    const ClassImage a = random_blobs(1, size), b = random_blobs(2, size);
    for (int cls : {1, 2}) {
      const double fast = ktc_ssim(as_double(a, cls), as_double(b, cls));
      EXPECT_NEAR(fast, brute_force_ssim(as_double(a, cls), as_double(b, cls)), 1e-10) << size;
    }
  }
  // Masks of more rows than columns: the mask's runs go down its columns.
  const ClassImage tall = random_blobs(7, 37).topLeftCorner(37, 24),
                   other = random_blobs(8, 37).topLeftCorner(37, 24);
  EXPECT_NEAR(ktc_ssim(as_double(tall, 1), as_double(other, 1)),
              brute_force_ssim(as_double(tall, 1), as_double(other, 1)), 1e-10);
  // Not only masks: any values.
  const Eigen::MatrixXd x = Eigen::MatrixXd::Random(20, 20), y = Eigen::MatrixXd::Random(20, 20);
  EXPECT_NEAR(ktc_ssim(x, y), brute_force_ssim(x, y), 1e-10);
}

// The same on KTC's grid, each windowed mean a direct separable sum (the window is a product of
// two 1-D kernels), for the threshold masks a sweep scores.
double separable_ssim(const Eigen::MatrixXd& t, const Eigen::MatrixXd& r) {
  const Eigen::Index n = t.rows();
  Eigen::MatrixXd g(n, n);  // g(i, k): the 1-D kernel at offset i - k
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index k = 0; k < n; ++k) {
      const double d = static_cast<double>(i - k);
      g(i, k) = std::abs(d) > 160 ? 0.0 : std::exp(-0.5 * d * d / 6400.0);
    }
  const Eigen::VectorXd weight = g.rowwise().sum();  // the kernel's coverage along one axis
  auto mean = [&](const Eigen::MatrixXd& x) {
    Eigen::MatrixXd across = Eigen::MatrixXd::Zero(n, n), both = across;
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index l = 0; l < n; ++l)
        for (Eigen::Index i = 0; i < n; ++i) across(i, j) += g(j, l) * x(i, l);
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index k = 0; k < n; ++k)
        for (Eigen::Index i = 0; i < n; ++i) both(i, j) += g(i, k) * across(k, j);
    return Eigen::MatrixXd(both.array() / (weight * weight.transpose()).array());
  };
  const Eigen::MatrixXd mt = mean(t), mr = mean(r), tt = mean(t.cwiseProduct(t)),
                        rr = mean(r.cwiseProduct(r)), tr = mean(t.cwiseProduct(r));
  const double c1 = 1e-4, c2 = 9e-4;
  double total = 0;
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    const double a = mt.data()[k], b = mr.data()[k];
    total += (2 * a * b + c1) * (2 * (tr.data()[k] - a * b) + c2) /
             ((a * a + b * b + c1) * (tt.data()[k] - a * a + rr.data()[k] - b * b + c2));
  }
  return total / static_cast<double>(t.size());
}

TEST(KtcScore, EveryThresholdMaskOnKtcsGridEqualsTheDirectSum) {
  // A smooth image's thresholds, as a sweep takes them: runs of ones a few a column, empty
  // columns, a mask touching the edges, and an empty one.
  const int n = kKtcImageSize;
  Eigen::MatrixXd x(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      x(i, j) = std::exp(-std::hypot(i - 60, j - 90) / 30.0) -
                0.8 * std::exp(-std::hypot(i - 190, j - 170) / 40.0) +
                0.3 * std::sin(i / 9.0) * std::cos(j / 13.0);
  // The reference itself against the definition summed pixel by pixel, where that is quick.
  const ClassImage a = random_blobs(1, 24), b = random_blobs(2, 24);
  EXPECT_NEAR(separable_ssim(as_double(a, 1), as_double(b, 1)),
              brute_force_ssim(as_double(a, 1), as_double(b, 1)), 1e-12);
  const ClassImage truth = random_blobs(6);
  const KtcScorer scorer(truth);
  for (double f : {-2.0, 0.2, 0.5, 0.9, 2.0}) {
    const Eigen::MatrixXd mask = (x.array() >= f).cast<double>().matrix();
    for (int cls : {1, 2})
      EXPECT_NEAR(scorer.ssim(cls, mask), separable_ssim(as_double(truth, cls), mask), 1e-10)
          << f << " " << cls;
  }
}

TEST(KtcScore, IdenticalMasksScoreOneAndKnownCasesTheirValue) {
  const ClassImage truth = random_blobs(3);
  EXPECT_NEAR(ktc_score(truth, truth).total(), 1.0, 1e-12);
  // Water everywhere against conductive everywhere: the resistive masks agree (SSIM 1); the
  // conductive ones have means 0 and 1 and no variance, so SSIM = c1 c2 / ((1 + c1) c2).
  const ClassImage water = ClassImage::Zero(256, 256), metal = ClassImage::Constant(256, 256, 2);
  const KtcScore s = ktc_score(water, metal);
  EXPECT_NEAR(s.resistive, 1.0, 1e-12);
  EXPECT_NEAR(s.conductive, 1e-4 / (1 + 1e-4), 1e-12);
  EXPECT_NEAR(s.total(), 0.5 * (1 + 1e-4 / (1 + 1e-4)), 1e-12);
  // A reconstruction of another size scores 0; a truth of another size is refused.
  EXPECT_EQ(ktc_score(truth, ClassImage::Zero(255, 256)).total(), 0.0);
  EXPECT_EQ(testing::input_error_at([&] { ktc_score(ClassImage::Zero(128, 128), truth); }),
            "truth.size");
  // Worse with every pixel moved away from the truth; the scorer equals the function.
  const ClassImage other = random_blobs(4);
  const KtcScorer scorer(truth);
  EXPECT_LT(scorer(other).total(), 0.9);
  EXPECT_EQ(scorer(other).total(), ktc_score(truth, other).total());
}

TEST(KtcSegmentation, OtsuSplitsThreeClustersAndWaterIsTheLargest) {
  // Values around -1 (few), 0 (many) and +2 (few): thresholds fall between the clusters.
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 0.05);
  Eigen::VectorXd v(1000);
  for (int i = 0; i < 1000; ++i) v[i] = (i < 100 ? -1.0 : i < 900 ? 0.0 : 2.0) + noise(rng);
  const auto [t1, t2] = otsu3_thresholds(v);
  // The three classes are the three clusters.
  for (int i = 0; i < 1000; ++i) {
    const int cls = v[i] < t1 ? 0 : v[i] < t2 ? 1 : 2;
    EXPECT_EQ(cls, i < 100 ? 0 : i < 900 ? 1 : 2) << i << ": " << v[i];
  }
  // On the label scale x = -dsigma/sigma_0: x > 0 resistive, x < 0 conductive.
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(256, 256);
  x.block(10, 10, 20, 20).setConstant(1.0);     // resistive
  x.block(100, 100, 30, 30).setConstant(-3.0);  // conductive
  x(255, 255) = std::nan("");                   // outside the tank: water
  const ClassImage otsu = segment(x, {});
  EXPECT_EQ(otsu(15, 15), 1);
  EXPECT_EQ(otsu(110, 110), 2);
  EXPECT_EQ(otsu(200, 50), 0);
  EXPECT_EQ(otsu(255, 255), 0);
  // Levels: fractions of max |x| = 3. Resistive needs x >= 0.5 * 3: the block at 1 is water.
  SegmentationRule levels{SegmentationKind::levels, 0.5, 0.5};
  const ClassImage l = segment(x, levels);
  EXPECT_EQ(l(15, 15), 0);
  EXPECT_EQ(l(110, 110), 2);
  levels.resistive = 0.3;
  EXPECT_EQ(segment(x, levels)(15, 15), 1);
  levels.conductive = 0;
  EXPECT_EQ(testing::input_error_at([&] { segment(x, levels); }), "SegmentationRule.conductive");
}

TEST(KtcSegmentation, TheGridMapsTheModelOntoKtcsImageInEitherOrientation) {
  const int L = 32;
  for (const KtcOrientation o : {KtcOrientation{0.3, false}, KtcOrientation{-1.2, true}}) {
    // Electrode e lies at image angle theta_1 -+ 2 pi e / L; the model puts it at 2 pi e / L.
    for (int e : {0, 5, 17}) {
      const double phi = o.first_electrode_angle + (o.clockwise ? -1 : 1) * 2 * M_PI * e / L;
      const Eigen::Vector2d m = o.to_model({std::cos(phi), std::sin(phi)});
      EXPECT_NEAR(m.x(), std::cos(2 * M_PI * e / L), 1e-12);
      EXPECT_NEAR(m.y(), std::sin(2 * M_PI * e / L), 1e-12);
    }
  }
  // A linear image x = model x-coordinate is reproduced exactly away from the rim; outside the
  // tank is NaN.
  const PixelGrid grid(32, 0.115);
  Eigen::VectorXd image = Eigen::VectorXd::Zero(grid.num_pixels());
  for (int i = 0; i < 32; ++i)
    for (int j = 0; j < 32; ++j)
      if (grid.mask()[i * 32 + j]) image[i * 32 + j] = grid.center(i, j).x();
  const KtcOrientation o{0.7, true};
  const Eigen::MatrixXd k = to_ktc_grid(image, grid, o);
  const double w = 0.23 / 256;
  for (int i : {60, 128, 190})
    for (int j : {70, 128, 170}) {
      const Eigen::Vector2d p(-0.115 + (j + 0.5) * w, 0.115 - (i + 0.5) * w);
      EXPECT_NEAR(k(i, j), o.to_model(p).x(), 1e-12) << i << " " << j;
    }
  EXPECT_TRUE(std::isnan(k(0, 0)));
  EXPECT_TRUE(std::isnan(k(255, 3)));
}

TEST(KtcFiles, TheReconstructionFileReadsBackAsKtcsUint8Matrix) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "eitbench_ktc_files_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const ClassImage img = random_blobs(6);
  const std::string path = (dir / "1.mat").string();
  write_ktc_reconstruction(path, img);
  const auto arrays = detail::read_mat_v5(read_file_bytes(path), path);
  ASSERT_EQ(arrays.size(), 1u);
  EXPECT_EQ(arrays[0].name, "reconstruction");
  EXPECT_EQ(arrays[0].kind, "uint8");
  ASSERT_EQ(arrays[0].shape, (std::vector<std::size_t>{256, 256}));
  for (int i = 0; i < 256; ++i)
    for (int j = 0; j < 256; ++j)
      ASSERT_EQ(arrays[0].values[static_cast<std::size_t>(i * 256 + j)], img(i, j)) << i << j;
  // A truth file is the same matrix under another name: read back, it is the image.
  detail::MatMatrix m{"truth", 256, 256, std::vector<double>(img.data(), img.data() + img.size()),
                      true};
  write_bytes_atomically((dir / "true1.mat").string(), detail::mat_v5_bytes({m}));
  EXPECT_EQ(read_ktc_truth((dir / "true1.mat").string()), img);
  // Bad images are refused, and nothing is written.
  EXPECT_EQ(testing::input_error_at([&] {
              write_ktc_reconstruction((dir / "2.mat").string(), ClassImage::Zero(10, 10));
            }),
            (dir / "2.mat").string() + ".reconstruction");
  EXPECT_FALSE(fs::exists(dir / "2.mat"));
  m.values[5] = 3;
  write_bytes_atomically((dir / "true2.mat").string(), detail::mat_v5_bytes({m}));
  EXPECT_EQ(testing::input_error_at([&] { read_ktc_truth((dir / "true2.mat").string()); }),
            (dir / "true2.mat").string() + ".truth");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace eitbench
