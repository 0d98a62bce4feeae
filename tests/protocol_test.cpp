// The measurement protocol of docs/conventions.md, for several L.
#include <gtest/gtest.h>

#include <random>

#include "eitbench/jacobian.h"

namespace eitbench {
namespace {

TEST(Protocol, SizesForAnyL) {
  for (int L : {4, 8, 16, 32}) {
    const Protocol p(L);
    EXPECT_EQ(p.frame_size(), L * (L - 3));
    EXPECT_EQ(p.reduced_size(), L * (L - 3) / 2);
    EXPECT_EQ(static_cast<int>(p.pairs(MeasurementOrder::ascending).size()), L * (L - 3));
  }
  EXPECT_EQ(Protocol(16).frame_size(), 208);
  EXPECT_EQ(Protocol(16).reduced_size(), 104);
  // L comes from a sensor, a file or a flag: bad input, not a programming error.
  try {
    Protocol(3);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "Protocol");
    EXPECT_EQ(e.field(), "electrodes");
  }
}

TEST(Protocol, RotatingOrderIsTheElectricalImpedanceMap) {
  const Protocol p(16);
  const auto& pairs = p.pairs(MeasurementOrder::rotating);
  for (int d = 0; d < 16; ++d)
    for (int k = 0; k < 13; ++k) {
      EXPECT_EQ(pairs[d * 13 + k].drive, d);
      EXPECT_EQ(pairs[d * 13 + k].measure, (d + 2 + k) % 16);
    }
}

TEST(Protocol, AscendingOrderSkipsTheDrivePairNeighbours) {
  const Protocol p(16);
  const auto& pairs = p.pairs(MeasurementOrder::ascending);
  std::vector<int> drive0, drive5, drive15;
  for (const auto& pr : pairs) {
    if (pr.drive == 0) drive0.push_back(pr.measure);
    if (pr.drive == 5) drive5.push_back(pr.measure);
    if (pr.drive == 15) drive15.push_back(pr.measure);
  }
  EXPECT_EQ(drive0, (std::vector<int>{2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14}));
  EXPECT_EQ(drive5, (std::vector<int>{0, 1, 2, 3, 7, 8, 9, 10, 11, 12, 13, 14, 15}));
  EXPECT_EQ(drive15, (std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13}));
}

TEST(Protocol, ReducedValuesAreThePapersSequential104) {
  const Protocol p(16);
  const auto& r = p.reduced_pairs();
  std::vector<int> per_drive(16, 0);
  for (const auto& pr : r) {
    EXPECT_LT(pr.drive, pr.measure);
    EXPECT_GE(pr.measure - pr.drive, 2);
    EXPECT_FALSE(pr.drive == 0 && pr.measure == 15);
    ++per_drive[pr.drive];
  }
  EXPECT_EQ(per_drive, (std::vector<int>{13, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0, 0}));
  EXPECT_EQ(r.front(), (MeasurementPair{0, 2}));
  EXPECT_EQ(r[13], (MeasurementPair{1, 3}));
  EXPECT_EQ(r.back(), (MeasurementPair{13, 15}));
  for (std::size_t i = 1; i < r.size(); ++i)  // row-major
    EXPECT_TRUE(r[i - 1].drive < r[i].drive ||
                (r[i - 1].drive == r[i].drive && r[i - 1].measure < r[i].measure));
}

TEST(Protocol, ReorderReduceExpandRoundTrips) {
  for (int L : {8, 16, 32}) {
    const Protocol p(L);
    std::mt19937 rng(L);
    std::normal_distribution<double> n;
    Eigen::VectorXd reduced(p.reduced_size());
    for (auto& x : reduced) x = n(rng);
    for (auto order : {MeasurementOrder::rotating, MeasurementOrder::ascending}) {
      const Eigen::VectorXd full = p.expand(reduced, order);
      EXPECT_EQ(p.reduce(full, order), reduced);
      EXPECT_EQ(p.reciprocity_error(full, order), 0.0);  // expanded frames are reciprocal
      const auto& pairs = p.pairs(order);
      for (int i = 0; i < p.frame_size(); ++i)
        EXPECT_EQ(full[i], full[p.index(pairs[i].measure, pairs[i].drive, order)]);
    }
    const Eigen::VectorXd rot = p.expand(reduced, MeasurementOrder::rotating);
    const Eigen::VectorXd asc =
        p.reorder(rot, MeasurementOrder::rotating, MeasurementOrder::ascending);
    EXPECT_EQ(asc, p.expand(reduced, MeasurementOrder::ascending));
    EXPECT_EQ(p.reorder(asc, MeasurementOrder::ascending, MeasurementOrder::rotating), rot);
    // Row selection matches frame selection.
    const Eigen::MatrixXd rows = rot;
    EXPECT_EQ(Eigen::VectorXd(p.select_rows(rows, MeasurementOrder::ascending, false)), asc);
    EXPECT_EQ(Eigen::VectorXd(p.select_rows(rows, MeasurementOrder::rotating, true)), reduced);
  }
}

TEST(Protocol, ReciprocityErrorMeasuresAsymmetry) {
  const Protocol p(16);
  Eigen::VectorXd v = p.expand(Eigen::VectorXd::Ones(104), MeasurementOrder::rotating);
  v[p.index(0, 2, MeasurementOrder::rotating)] = 3;  // one value off by 2 against its partner 1
  EXPECT_NEAR(p.reciprocity_error(v, MeasurementOrder::rotating), std::sqrt(4.0) / v.norm(), 1e-15);
  // A frame is data: one of the wrong length is bad input.
  EXPECT_THROW(p.reorder(Eigen::VectorXd::Ones(207), MeasurementOrder::rotating,
                         MeasurementOrder::ascending),
               InputError);
  EXPECT_THROW(p.expand(Eigen::VectorXd::Ones(103), MeasurementOrder::rotating), InputError);
  try {
    parse_order("descending");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "MeasurementOrder: name: unknown measurement order "
              "'descending' (rotating or ascending)");
  }
}

}  // namespace
}  // namespace eitbench
