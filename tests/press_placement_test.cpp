// The placement map against a bias that is known because it was made: presses put too far out
// and turned by an amount that depends on their radius, as one-step images put them on a real
// skin; and the symmetries a radial map must keep.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "eitbench/bench/methods/press_placement.h"
#include "test_support.h"

namespace eitbench {
namespace {

struct Presses {
  std::vector<Eigen::Vector2d> truth, found;
};

// n presses spread evenly over the disk of radius `radius`, each put where `put` says (on the
// unit disk) plus Gaussian scatter `sigma` x radius.
template <typename Put>
Presses presses(int n, unsigned seed, double radius, double sigma, Put put) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), angle(-M_PI, M_PI);
  std::normal_distribution<double> scatter(0, sigma);
  Presses p;
  for (int i = 0; i < n; ++i) {
    const double r = std::sqrt(u(rng)), a = angle(rng);
    const Eigen::Vector2d t(r * std::cos(a), r * std::sin(a));
    p.truth.push_back(radius * t);
    p.found.push_back(radius * (put(t) + Eigen::Vector2d(scatter(rng), scatter(rng))));
  }
  return p;
}

// Inner presses pushed out towards half the radius and turned clockwise, by up to 30 degrees at
// the centre: the pattern the one-step methods show on the hydrogel skin.
Eigen::Vector2d biased(const Eigen::Vector2d& t) {
  const double r = t.norm();
  return (0.4 + 0.5 * r) / std::max(r, 1e-12) * (Eigen::Rotation2Dd(-M_PI / 6 * (1 - r)) * t);
}

double mean_error(const std::vector<Eigen::Vector2d>& at,
                  const std::vector<Eigen::Vector2d>& truth) {
  double sum = 0;
  for (std::size_t i = 0; i < at.size(); ++i) sum += (at[i] - truth[i]).norm();
  return sum / static_cast<double>(at.size());
}

TEST(PlacementMap, UndoesAKnownRadialBiasOnNewPresses) {
  const Presses labelled = presses(400, 1, 1.0, 0.01, biased);
  const Presses fresh = presses(200, 2, 1.0, 0.01, biased);
  const PlacementMap map(labelled.found, labelled.truth, 1.0);
  const double raw = mean_error(fresh.found, fresh.truth);
  const double mapped = mean_error(map.apply(fresh.found), fresh.truth);
  EXPECT_GT(raw, 0.1);  // the made bias is large: the test can tell a map that works
  EXPECT_LT(mapped, 0.04) << "raw " << raw;
  EXPECT_LT(map.leave_one_out_error(), 0.04);
  EXPECT_GT(map.bandwidth(), 0);
  EXPECT_EQ(map.presses(), 400);
}

TEST(PlacementMap, LeavesUnbiasedPressesAboutWhereTheyWere) {
  const auto none = [](const Eigen::Vector2d& t) { return t; };
  const Presses labelled = presses(400, 3, 1.0, 0.03, none);
  const Presses fresh = presses(200, 4, 1.0, 0.03, none);
  const PlacementMap map(labelled.found, labelled.truth, 1.0);
  const double raw = mean_error(fresh.found, fresh.truth);
  EXPECT_LT(mean_error(map.apply(fresh.found), fresh.truth), 1.15 * raw) << raw;
  EXPECT_EQ(map.apply(Eigen::Vector2d::Zero()), Eigen::Vector2d::Zero());  // no direction to turn
}

// A radial map commutes with turning the sensor, and scales with its radius.
TEST(PlacementMap, TurnsWithTheSensorAndScalesWithItsRadius) {
  const Presses p = presses(100, 5, 1.0, 0.02, biased);
  const PlacementMap map(p.found, p.truth, 1.0);
  const Eigen::Rotation2Dd turn(0.7);
  Presses turned, scaled;
  for (std::size_t i = 0; i < p.truth.size(); ++i) {
    turned.truth.push_back(turn * p.truth[i]), turned.found.push_back(turn * p.found[i]);
    scaled.truth.push_back(2.0 * p.truth[i]), scaled.found.push_back(2.0 * p.found[i]);
  }
  const PlacementMap map_turned(turned.found, turned.truth, 1.0);
  const PlacementMap map_scaled(scaled.found, scaled.truth, 2.0);
  EXPECT_NEAR(map_scaled.bandwidth(), 2 * map.bandwidth(), 1e-12);
  const Eigen::Vector2d query(0.3, -0.2);
  EXPECT_LT((map_turned.apply(turn * query) - turn * map.apply(query)).norm(), 1e-9);
  EXPECT_LT((map_scaled.apply(2.0 * query) - 2.0 * map.apply(query)).norm(), 1e-9);
}

// Presses put at the centre carry no direction: they count in the radius, not in the turn.
TEST(PlacementMap, PressesAtTheCentreDoNotPullTheTurn) {
  Presses p = presses(200, 7, 1.0, 0.0, biased);
  PlacementMapOptions one_width;  // the same width for both: only the presses differ
  one_width.bandwidths = {0.05};
  const PlacementMap clean(p.found, p.truth, 1.0, one_width);
  for (int i = 0; i < 50; ++i)
    p.found.push_back(Eigen::Vector2d::Zero()), p.truth.push_back(p.truth[i]);
  for (int i = 0; i < 50; ++i)
    p.found.push_back(p.found[i]), p.truth.push_back(Eigen::Vector2d::Zero());
  const PlacementMap mixed(p.found, p.truth, 1.0, one_width);
  const Eigen::Vector2d query = biased(Eigen::Vector2d(0.2, 0.0));
  const auto turn = [](const Eigen::Vector2d& a, const Eigen::Vector2d& q) {
    return std::remainder(std::atan2(a.y(), a.x()) - std::atan2(q.y(), q.x()), 2 * M_PI);
  };
  // Made: 30 (1 - 0.2) = 24 degrees clockwise at 0.2 R, undone counter-clockwise.
  EXPECT_NEAR(turn(clean.apply(query), query), 24 * M_PI / 180, 2 * M_PI / 180);
  EXPECT_NEAR(turn(mixed.apply(query), query), turn(clean.apply(query), query), 1e-12);
}

// A spot pressed many times cannot vouch for itself: left out with its repeats, the narrowest
// width is not chosen for recall.
TEST(PlacementMap, LeavesOutEveryPressAtTheSamePosition) {
  const Presses p = presses(60, 8, 1.0, 0.05, [](const Eigen::Vector2d& t) { return t; });
  Presses repeated;
  for (int k = 0; k < 5; ++k)
    for (std::size_t i = 0; i < p.truth.size(); ++i)
      repeated.truth.push_back(p.truth[i]), repeated.found.push_back(p.found[i]);
  const PlacementMap map(repeated.found, repeated.truth, 1.0);
  const PlacementMap once(p.found, p.truth, 1.0);
  EXPECT_NEAR(map.bandwidth(), once.bandwidth(), 1e-12);
  EXPECT_GT(map.leave_one_out_error(), 0.02);
}

TEST(PlacementMap, RefusesWhatItCannotUse) {
  const Presses p = presses(20, 6, 1.0, 0.02, biased);
  auto field = [&](auto make) { return testing::input_error_at(make); };
  EXPECT_EQ(field([&] {
              PlacementMap(p.found, {p.truth.begin(), p.truth.end() - 1}, 1.0);
            }),
            "placement map.truth");
  EXPECT_EQ(field([&] {
              PlacementMap({p.found.begin(), p.found.begin() + 5},
                           {p.truth.begin(), p.truth.begin() + 5}, 1.0);
            }),
            "placement map.presses");
  EXPECT_EQ(field([&] { PlacementMap(p.found, p.truth, 0.0); }), "placement map.radius");
  PlacementMapOptions o;
  o.bandwidths = {0.1, -1};
  EXPECT_EQ(field([&] { PlacementMap(p.found, p.truth, 1.0, o); }), "placement map.bandwidths");
  o = PlacementMapOptions();
  o.min_presses = 1;
  EXPECT_EQ(field([&] { PlacementMap(p.found, p.truth, 1.0, o); }), "placement map.min_presses");
  const std::vector<Eigen::Vector2d> spot(12, Eigen::Vector2d(0.3, 0.1));
  EXPECT_EQ(field([&] { PlacementMap(spot, spot, 1.0); }), "placement map.presses");
  Presses bad = p;
  bad.found[3].x() = NAN;
  EXPECT_EQ(field([&] { PlacementMap(bad.found, bad.truth, 1.0); }), "placement map.positions");
}

}  // namespace
}  // namespace eitbench
