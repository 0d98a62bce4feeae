// Simulated tanks like KTC2023's: the targets' geometry, the labels' grid and orientation, the
// frames against the forward model, the noise asked for and its measurement from repeated
// patterns, and (where ../shared has the challenge's files) the real frames' noise and size.
#include <gtest/gtest.h>

#include <tbb/global_control.h>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "eitbench/bench/ktc/ktc_learned.h"
#include "eitbench/bench/ktc/tank_augmentation.h"
#include "eitbench/bench/ktc/tank_simulation.h"
#include "ktc_synthetic.h"
#include "test_support.h"

namespace eitbench {
namespace {

constexpr double kR = 0.115;

TEST(KtcSimulation, TargetsLieInsideTheTankApartAndWithinTheirSizes) {
  KtcSimulationOptions o;
  std::mt19937_64 rng(4);
  int polygons = 0, blobs = 0, discs = 0, classes[3] = {0, 0, 0};
  for (int n = 0; n < 300; ++n) {
    const auto targets = draw_ktc_targets(rng, o, kR);
    ASSERT_GE(targets.size(), 1u);
    ASSERT_LE(targets.size(), 3u);
    for (std::size_t a = 0; a < targets.size(); ++a) {
      const KtcTarget& t = targets[a];
      EXPECT_GE(t.radius, o.smallest * kR);
      EXPECT_LE(t.radius, o.largest * kR);
      ++classes[t.cls];
      (t.corners ? polygons : t.harmonics.empty() ? discs : blobs)++;
      for (int k = 0; k < 360; ++k) {  // the boundary inside 0.9 R, outside every other target
        const double angle = k * 3.14159265358979 / 180;
        const Eigen::Vector2d p =
            t.centre + t.boundary(angle) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
        EXPECT_LT(p.norm(), 0.9 * kR + 1e-12);
        for (std::size_t b = 0; b < targets.size(); ++b) {
          if (b != a) {
            EXPECT_FALSE(targets[b].contains(p));
          }
        }
      }
    }
  }
  EXPECT_GT(polygons, 100);
  EXPECT_GT(blobs, 100);
  EXPECT_GT(discs, 100);
  EXPECT_GT(classes[1], 200);
  EXPECT_GT(classes[2], 200);
}

// A band of contrasts: each target's drawn log-uniformly within its class's band, the mesh's
// conductivity following it; a spread of 1 leaves the targets drawn as without one.
TEST(KtcSimulation, ABandOfContrastsDrawsEachTargetWithinIt) {
  KtcSimulationOptions o;
  o.resistive = std::sqrt(0.01 * 0.1), o.conductive = std::sqrt(10.0 * 100),
  o.contrast_spread = std::sqrt(10.0);
  std::mt19937_64 rng(9);
  double log_sum = 0;
  int count = 0, low = 0, high = 0;
  for (int n = 0; n < 300; ++n)
    for (const KtcTarget& t : draw_ktc_targets(rng, o, kR)) {
      const double centre = t.cls == 1 ? o.resistive : o.conductive;
      const double u = std::log10(t.contrast / centre);  // uniform in [-0.5, 0.5]
      ASSERT_GE(u, -0.5 - 1e-12);
      ASSERT_LE(u, 0.5 + 1e-12);
      log_sum += u, ++count;
      low += u<-0.4, high += u> 0.4;
    }
  EXPECT_NEAR(log_sum / count, 0.0, 0.05);  // sd of the mean 0.29 / sqrt(600)
  EXPECT_GT(low, count / 20);               // both ends of the band reached (10 % each)
  EXPECT_GT(high, count / 20);
  // The conductivity of an element inside a target is the target's own.
  const Mesh mesh = testing::ktc_coarse_tank().mesh;
  std::mt19937_64 one(3);
  const auto targets = draw_ktc_targets(one, o, kR);
  const Eigen::VectorXd sigma = ktc_conductivity(mesh, 0.8, targets, o);
  int inside = 0;
  for (int e = 0; e < mesh.num_triangles(); ++e)
    for (const KtcTarget& t : targets)
      if (t.contains(triangle_centroid(mesh, e))) {
        EXPECT_DOUBLE_EQ(sigma[e], 0.8 * t.contrast);
        ++inside;
      }
  EXPECT_GT(inside, 0);
  // Without a spread, the same targets as ever and no contrast of their own.
  KtcSimulationOptions plain;
  std::mt19937_64 a(5), b(5);
  const auto with = draw_ktc_targets(a, plain, kR);
  for (const KtcTarget& t : with) EXPECT_EQ(t.contrast, 0.0);
  o.contrast_spread = 1;
  const auto without = draw_ktc_targets(b, o, kR);
  ASSERT_EQ(with.size(), without.size());
  for (std::size_t k = 0; k < with.size(); ++k) EXPECT_EQ(with[k].centre, without[k].centre);
  o.contrast_spread = 0.5;
  EXPECT_THROW(o.validate(), InputError);
  o.contrast_spread = 40;  // 0.0316 * 40 > 1: no longer resistive
  EXPECT_THROW(o.validate(), InputError);
}

// A square of circumradius 1 covers 2, a hexagon 3 sqrt(3) / 2: counted on a fine grid.
TEST(KtcSimulation, APolygonTargetIsThatPolygon) {
  for (int corners : {4, 6}) {
    KtcTarget t;
    t.radius = 1, t.corners = corners, t.phase = 0.3;
    int inside = 0;
    const int n = 1000;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        inside += t.contains({-1 + (i + 0.5) * 2.0 / n, -1 + (j + 0.5) * 2.0 / n});
    const double area = inside * 4.0 / (n * n);
    EXPECT_NEAR(area, corners == 4 ? 2.0 : 3 * std::sqrt(3.0) / 2, 0.01) << corners;
    EXPECT_NEAR(t.boundary(0.3), 1.0, 1e-12);  // a corner
  }
}

// The labels lie on KTC's image grid (row 0 at the top) where the orientation puts the targets.
TEST(KtcSimulation, LabelsFollowTheOrientationOfTheImage) {
  KtcSimulationOptions o;
  o.grid = 128;
  for (bool clockwise : {false, true}) {
    o.orientation.clockwise = clockwise;
    const Eigen::Vector2d image_point(0.05, 0.04);  // right of and above the centre
    KtcTarget t;
    t.centre = o.orientation.to_model(image_point), t.radius = 0.02, t.cls = 2;
    const ClassImage labels = ktc_labels({t}, kR, o);
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int count = 0;
    const double w = 2 * kR / o.grid;
    for (int i = 0; i < o.grid; ++i)
      for (int j = 0; j < o.grid; ++j)
        if (labels(i, j) == 2)
          sum += Eigen::Vector2d(-kR + (j + 0.5) * w, kR - (i + 0.5) * w), ++count;
    EXPECT_NEAR(count * w * w, 3.14159265 * 0.02 * 0.02, 0.05 * 3.14159265 * 0.02 * 0.02);
    EXPECT_LT((sum / count - image_point).norm(), 0.5 * w) << clockwise;  // a rasterised disc
    EXPECT_EQ((labels.array() == 1).count(), 0);
  }
}

TEST(KtcSimulation, FramesAreTheModelsChangeWithTheNoiseAskedForOnAnyThreads) {
  const KtcTank tank = testing::ktc_coarse_tank();
  KtcSimulationOptions o;
  o.samples = 12;
  const KtcSimulatedSet clean = simulate_ktc_tanks(tank, o);
  const Eigen::VectorXd empty =
      tank.model->measured(Eigen::VectorXd::Constant(tank.mesh.num_triangles(), 0.8));
  for (int n = 0; n < o.samples; ++n) {
    const Eigen::VectorXd v =
        tank.model->measured(ktc_conductivity(tank.mesh, 0.8, clean.targets[n], o)) - empty;
    EXPECT_LT((clean.frames.row(n).transpose() - v).norm(), 1e-12 * v.norm()) << n;
    EXPECT_GT(v.norm(), 1e-4 * empty.norm()) << n;  // every tank holds a target it sees
    EXPECT_GT((clean.labels[n].array() > 0).count(), 0) << n;
  }
  o.noise = 1e-3;
  const KtcSimulatedSet noisy = simulate_ktc_tanks(tank, o);
  const Eigen::MatrixXd added = noisy.frames - clean.frames;
  EXPECT_NEAR(std::sqrt(added.squaredNorm() / added.size()), 1e-3, 0.03e-3);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  EXPECT_EQ(simulate_ktc_tanks(tank, o).frames, noisy.frames);
  o.resistive = 2;
  EXPECT_THROW(simulate_ktc_tanks(tank, o), InputError);
}

// Gaussian noise of a known level, measured back from the 8 pairs KTC drives twice.
TEST(KtcSimulation, RepeatedPatternsMeasureTheNoise) {
  const KtcTank tank = testing::ktc_coarse_tank();
  Eigen::VectorXd frame =
      tank.model->measured(Eigen::VectorXd::Constant(tank.mesh.num_triangles(), 0.8));
  std::mt19937_64 rng(9);
  std::normal_distribution<double> noise(0, 2e-4);
  for (auto& v : frame) v += noise(rng);
  EXPECT_NEAR(repeated_pattern_noise(frame, tank.protocol->patterns()), 2e-4, 0.3e-4);
  CurrentPatterns once = testing::ktc_patterns();
  once.injection = once.injection.leftCols(16).eval();  // the odd pairs alone: none repeated
  EXPECT_THROW(repeated_pattern_noise(Eigen::VectorXd::Zero(16 * 31), once), InputError);
}

// The learned rows train on tanks with the noise the reference's repeated patterns measure, the
// noise their report names: not noise-free frames.
TEST(KtcSimulation, TheLearnedRowsTanksCarryTheReferencesNoise) {
  KtcTank tank = testing::ktc_coarse_tank();
  tank.reference = tank.model->measured(Eigen::VectorXd::Constant(tank.mesh.num_triangles(), 0.8));
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0, 2e-4);
  for (auto& v : tank.reference) v += noise(rng);
  KtcLearnedOptions learned;
  learned.tanks = 8;
  KtcSimulationOptions o = ktc_training_simulation(learned, tank);
  EXPECT_NEAR(o.noise, 2e-4, 0.3e-4);
  EXPECT_EQ(o.samples, 8);
  EXPECT_NEAR(o.resistive / o.contrast_spread, learned.resistive_low, 1e-12);
  EXPECT_NEAR(o.conductive * o.contrast_spread, learned.conductive_high, 1e-9);
  const KtcSimulatedSet noisy = simulate_ktc_tanks(tank, o);
  const double measured = o.noise;
  o.noise = 0;
  const Eigen::MatrixXd added = noisy.frames - simulate_ktc_tanks(tank, o).frames;
  EXPECT_NEAR(std::sqrt(added.squaredNorm() / added.size()), measured, 0.05 * measured);
}

// to_image undoes to_model, mirrored or not.
TEST(KtcSimulation, AnOrientationsImagePointIsItsModelPointsInverse) {
  for (bool clockwise : {false, true}) {
    KtcOrientation o;
    o.clockwise = clockwise, o.first_electrode_angle = 0.7;
    const Eigen::Vector2d p(0.03, -0.05);
    EXPECT_LT((o.to_image(o.to_model(p)) - p).norm(), 1e-15) << clockwise;
    EXPECT_LT((o.to_model(o.to_image(p)) - p).norm(), 1e-15) << clockwise;
  }
}

// Two discs in the tank, and the same discs moved by each of KTC's 8 elements: the augmented
// set's frames and labels are the moved tank's, as the forward model and the label grid give them.
TEST(KtcAugmentation, AMovedSampleIsTheMovedTanksFrameAndLabels) {
  const KtcTank tank = testing::ktc_coarse_tank();
  const CurrentPatterns& patterns = tank.protocol->patterns();
  const std::vector<GroupElement> group = ktc_group(patterns);
  ASSERT_EQ(group.size(), 8u);
  KtcSimulationOptions o;
  const Eigen::VectorXd empty =
      tank.model->measured(Eigen::VectorXd::Constant(tank.mesh.num_triangles(), 0.8));
  auto sample = [&](const std::vector<KtcTarget>& targets, KtcSimulatedSet& set) {
    const Eigen::VectorXd v =
        tank.model->measured(ktc_conductivity(tank.mesh, 0.8, targets, o)) - empty;
    set.frames.conservativeResize(set.frames.rows() + 1, v.size());
    set.frames.bottomRows(1) = v.transpose();
    set.labels.push_back(ktc_labels(targets, kR, o));
  };
  KtcTarget a, b;
  a.centre = {0.04, 0.03}, a.radius = 0.02, a.cls = 1;
  b.centre = {-0.05, -0.01}, b.radius = 0.025, b.cls = 2;
  KtcSimulatedSet one;
  sample({a, b}, one);
  const KtcSimulatedSet augmented = augment_ktc_set(one, patterns, group, o.orientation);
  ASSERT_EQ(augmented.frames.rows(), 8);
  for (std::size_t k = 0; k < group.size(); ++k) {
    KtcTarget ga = a, gb = b;
    ga.centre = transform_point(a.centre, group[k], 32);
    gb.centre = transform_point(b.centre, group[k], 32);
    KtcSimulatedSet moved;
    sample({ga, gb}, moved);
    const Eigen::VectorXd got = augmented.frames.row(k).transpose();
    const Eigen::VectorXd want = moved.frames.row(0).transpose();
    EXPECT_LT((got - want).norm(), 1e-9 * want.norm()) << group[k].to_string();
    EXPECT_EQ(augmented.labels[k], moved.labels[0]) << group[k].to_string();
  }
  EXPECT_NE(augmented.labels[1], augmented.labels[0]);  // the labels did move
  // An eighth turn does not map the grid onto itself, nor a mirror with electrode 1 off the axes.
  EXPECT_THROW(move_ktc_labels(one.labels[0], {4, false}, o.orientation), InputError);
  KtcOrientation tilted;
  tilted.first_electrode_angle = 0.3;
  EXPECT_NO_THROW(move_ktc_labels(one.labels[0], {8, false}, tilted));
  EXPECT_THROW(move_ktc_labels(one.labels[0], {0, true}, tilted), InputError);
}

// Each sample's change from the empty tank, and its truth.
std::pair<std::vector<Eigen::VectorXd>, std::vector<ClassImage>> labelled_changes(
    const KtcFolder& folder, const KtcMeasurement& ref) {
  std::vector<Eigen::VectorXd> changes;
  std::vector<ClassImage> truths;
  for (const auto& s : folder.samples) {
    changes.push_back(read_ktc_measurement(s.data).voltages - ref.voltages);
    truths.push_back(read_ktc_truth(s.truth));
  }
  return {changes, truths};
}

// Tanks written with known contrasts (0.05 resistive, 20 conductive: ktc_synthetic.h) give them
// back from their truths, to the grid's step (a factor of 1.74).
TEST(KtcSimulation, TheContrastsFitBackFromLabelledTanks) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("eitbench_contrasts_" + std::to_string(::getpid()));
  testing::write_synthetic_ktc(dir, {{{0.03, 0.04, 0.025, 1}}, {{-0.04, -0.02, 0.03, 2}}});
  const KtcFolder folder = scan_ktc_folder(dir.string());
  const KtcMeasurement ref = read_ktc_measurement(folder.reference);
  KtcTankOptions to;  // the synthetic files' own tank
  const KtcTank tank = ktc_tank_at(ref, to, 0.8, Eigen::VectorXd::Constant(32, 5e-4));
  const auto [changes, truths] = labelled_changes(folder, ref);
  const KtcContrasts c = fit_ktc_contrasts(tank, changes, truths, {});
  // Held out: each sample left out in turn, the fit on the other alone; the first sample's
  // resistive disc alone still gives its contrast, the second's conductive one its own.
  const KtcContrastFits fits = fit_ktc_contrasts_held_out(tank, changes, truths, {});
  const KtcContrasts first = fit_ktc_contrasts(tank, {changes[0]}, {truths[0]}, {});
  const KtcContrasts second = fit_ktc_contrasts(tank, {changes[1]}, {truths[1]}, {});
  std::filesystem::remove_all(dir);
  EXPECT_EQ(fits.all.resistive, c.resistive);
  EXPECT_EQ(fits.all.conductive, c.conductive);
  ASSERT_EQ(fits.without.size(), 2u);
  EXPECT_EQ(fits.without[1].resistive, first.resistive);
  EXPECT_EQ(fits.without[0].conductive, second.conductive);
  EXPECT_NEAR(std::log10(first.resistive), std::log10(0.05), 0.25);
  EXPECT_NEAR(std::log10(second.conductive), std::log10(20.0), 0.25);
  EXPECT_NEAR(std::log10(c.resistive), std::log10(0.05), 0.25) << c.resistive;
  EXPECT_NEAR(std::log10(c.conductive), std::log10(20.0), 0.25) << c.conductive;
  EXPECT_LT(c.relative_residual, 0.1);
  EXPECT_THROW(fit_ktc_contrasts(tank, changes, {}, {}), InputError);
}

// A change simulated from its truth at contrasts on the fit's grid, with white noise: the misfit
// is the noise, over the values present. Against a truth elsewhere, the model explains little of
// the change, and the tanks' noise leaves that sample out.
TEST(KtcSimulation, TheModelMisfitIsTheNoiseWhereTheTruthDescribesTheChange) {
  const KtcTank tank = testing::ktc_coarse_tank();
  const double R = tank.options.radius, w = 2 * R / 256;
  auto disc = [&](double x, double y, double r, int cls, ClassImage& image) {
    for (int i = 0; i < 256; ++i)
      for (int j = 0; j < 256; ++j)
        if (std::hypot(-R + (j + 0.5) * w - x, R - (i + 0.5) * w - y) < r) image(i, j) = cls;
  };
  ClassImage truth = ClassImage::Zero(256, 256), elsewhere = truth;
  disc(0.04, 0.03, 0.025, 1, truth), disc(-0.05, -0.02, 0.03, 2, truth);
  disc(-0.06, 0.06, 0.02, 1, elsewhere);
  // The grid's end points (tank_contrasts.cpp): 10^-3 resistive, 10^3 conductive.
  Eigen::VectorXd sigma(tank.mesh.num_triangles());
  for (int t = 0; t < sigma.size(); ++t) {
    const Eigen::Vector2d q = KtcOrientation{}.to_image(triangle_centroid(tank.mesh, t));
    const int i = static_cast<int>(std::floor((R - q.y()) / w));
    const int j = static_cast<int>(std::floor((q.x() + R) / w));
    const int cls = i >= 0 && j >= 0 && i < 256 && j < 256 ? truth(i, j) : 0;
    sigma[t] = tank.background * (cls == 1   ? std::pow(10.0, -3.0)
                                  : cls == 2 ? std::pow(10.0, 0.1 + 2.9)
                                             : 1.0);
  }
  const Eigen::VectorXd clean =
      tank.model->measured(sigma) -
      tank.model->measured(Eigen::VectorXd::Constant(sigma.size(), tank.background));
  const double level = 0.1 * clean.norm() / std::sqrt(static_cast<double>(clean.size()));
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal(0, level);
  Eigen::VectorXd noise(clean.size());
  for (Eigen::Index k = 0; k < noise.size(); ++k) noise[k] = normal(rng);
  Eigen::VectorXd change = clean + noise;
  change[5] = std::numeric_limits<double>::quiet_NaN(), noise[5] = 0;  // a value the frame lacks
  const int present = static_cast<int>(change.size()) - 1;
  const std::vector<KtcMisfit> m =
      fit_ktc_contrasts_held_out(tank, {change, change}, {truth, elsewhere}, {}).own_misfits();
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].values, present);
  EXPECT_NEAR(m[0].rms, noise.norm() / std::sqrt(present), 0.02 * level);
  EXPECT_NEAR(m[0].relative, 0.1, 0.01);
  EXPECT_GT(m[1].relative, kKtcMisfitExplained);
  // The tanks' noise: the first sample's misfit alone; with it held out, no sample is left.
  EXPECT_DOUBLE_EQ(ktc_misfit_noise(m, m.size()), m[0].rms);
  EXPECT_DOUBLE_EQ(ktc_misfit_noise(m, 1), m[0].rms);
  EXPECT_TRUE(std::isnan(ktc_misfit_noise(m, 0)));
  // Pooled over the values: 2 mV on 100 values and 4 mV on 300 give sqrt(13e-6) V.
  const std::vector<KtcMisfit> made{{0.1, 2e-3, 100}, {0.2, 4e-3, 300}, {0.9, 1.0, 100}};
  EXPECT_NEAR(ktc_misfit_noise(made, made.size()), std::sqrt(13e-6), 1e-15);
  EXPECT_DOUBLE_EQ(ktc_misfit_noise(made, 1), 2e-3);
}

// The real frames: their noise from the repeated pairs, the targets' contrasts fitted to the four
// truths, and the size of a sample's change against the simulated tanks' at those contrasts.
TEST(KtcSimulation, TheRealFramesNoiseAndChangeBesideTheSimulatedOnes) {
  if (!std::filesystem::exists(testing::ktc_folder() + "/ref.mat"))
    GTEST_SKIP() << "no " << testing::ktc_folder() << " (not committed)";
  const KtcFolder folder = scan_ktc_folder(testing::ktc_folder());
  const KtcMeasurement ref = read_ktc_measurement(folder.reference);
  const double noise = repeated_pattern_noise(ref.voltages, ref.patterns);
  std::vector<double> changes;
  for (const auto& s : folder.samples) {
    const KtcMeasurement m = read_ktc_measurement(s.data);
    changes.push_back((m.voltages - ref.voltages).norm());
    const double own = repeated_pattern_noise(m.voltages, m.patterns);
    std::printf("%s: noise %.3g V, change %.3g V\n", s.data.c_str(), own, changes.back());
    EXPECT_GT(own, noise / 1.5) << s.data;  // the same noise in every frame (docs/ktc.md)
    EXPECT_LT(own, noise * 1.5) << s.data;
  }
  const double rms = ref.voltages.norm() / std::sqrt(ref.voltages.size());
  std::printf("reference: noise %.3g V (%.2g of its rms)\n", noise, noise / rms);
  EXPECT_LT(noise, 1e-3 * rms);
  std::sort(changes.begin(), changes.end());
  KtcTankOptions to;
  to.density = MeshDensity::coarse;
  const KtcTank tank = calibrate_ktc_tank(ref, to);
  const auto [measured, truths] = labelled_changes(folder, ref);
  const KtcContrasts fitted = fit_ktc_contrasts(tank, measured, truths, {});
  std::printf("contrasts: resistive %.3g, conductive %.3g, residual %.3f of the changes\n",
              fitted.resistive, fitted.conductive, fitted.relative_residual);
  EXPECT_LT(fitted.relative_residual, 0.6);  // the truths explain most of each change
  KtcSimulationOptions o;
  o.samples = 40, o.noise = noise;
  o.resistive = fitted.resistive, o.conductive = fitted.conductive;
  const KtcSimulatedSet set = simulate_ktc_tanks(tank, o);
  std::vector<double> simulated;
  for (int n = 0; n < o.samples; ++n) simulated.push_back(set.frames.row(n).norm());
  std::sort(simulated.begin(), simulated.end());
  std::printf("simulated change: %.3g / %.3g / %.3g V (10th, 50th, 90th percentile)\n",
              simulated[4], simulated[20], simulated[36]);
  // The simulated tanks change the frame as much as the real targets do, within a factor of 2.
  const double real_median = (changes[1] + changes[2]) / 2;
  EXPECT_GT(simulated[20], real_median / 2);
  EXPECT_LT(simulated[20], real_median * 2);
}

}  // namespace
}  // namespace eitbench
