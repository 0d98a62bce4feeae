// Electrodes shifted along the disk's rim (electrode_shift.h): the domain randomisation's
// misplaced electrodes.
#include <gtest/gtest.h>

#include <cmath>

#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
namespace {

std::vector<int> nodes_of(const Electrode& el) {
  std::vector<int> nodes;
  for (const auto& s : el.segments) nodes.insert(nodes.end(), {s[0], s[1]});
  return nodes;
}

std::vector<double> drawn_shifts(const Mesh& disk, std::uint64_t seed) {
  const double bound = max_neighbour_shift(disk) / 2;
  RandomStream rng(seed, 0);
  std::vector<double> shifts(disk.num_electrodes());
  for (auto& s : shifts) s = rng.uniform(-bound, bound);
  return shifts;
}

// Each electrode's nodes turned by exactly its own shift, its length kept, every node at its
// radius, the centre fixed, every triangle still counter-clockwise.
TEST(ElectrodeShift, MovesEachElectrodeRigidlyAlongTheRim) {
  const Mesh& disk = testing::disk(16, MeshDensity::medium);
  const std::vector<double> shifts = drawn_shifts(disk, 5);
  const Mesh moved = shift_electrodes(disk, shifts);
  EXPECT_NO_THROW(validate_mesh(moved, "shifted"));
  EXPECT_EQ(moved.triangles, disk.triangles);
  for (int e = 0; e < 16; ++e) {
    const double c = std::cos(shifts[e]), s = std::sin(shifts[e]);
    for (int n : nodes_of(disk.electrodes[e])) {
      const Eigen::Vector2d p = disk.nodes.row(n), q = moved.nodes.row(n);
      EXPECT_NEAR(q.x(), c * p.x() - s * p.y(), 1e-12) << "electrode " << e;
      EXPECT_NEAR(q.y(), s * p.x() + c * p.y(), 1e-12) << "electrode " << e;
    }
    EXPECT_NEAR(std::remainder(electrode_angle(moved, e) - electrode_angle(disk, e), 2 * M_PI),
                shifts[e], 1e-12);
    EXPECT_NEAR(moved.electrodes[e].length(moved.nodes), disk.electrodes[e].length(disk.nodes),
                1e-12);
  }
  EXPECT_LT((moved.nodes.rowwise().norm() - disk.nodes.rowwise().norm()).cwiseAbs().maxCoeff(),
            1e-12);
  // Nodes away from the rim move less than the rim at their angle: at most the largest shift.
  const double largest = Eigen::Map<const Eigen::VectorXd>(shifts.data(), 16).cwiseAbs().maxCoeff();
  EXPECT_LE((moved.nodes - disk.nodes).rowwise().norm().maxCoeff(), largest * (1 + 1e-9));
  EXPECT_EQ(shift_electrodes(disk, std::vector<double>(16, 0.0)).nodes, disk.nodes);
}

// A homogeneous disk cannot tell where its electrodes sit when all of them turn together: the
// frame is rotation invariant, up to the twisted interior's discretisation. One electrode moved
// alone changes it by far more.
TEST(ElectrodeShift, AllTurnedTogetherLeaveAHomogeneousFrame) {
  const Mesh& disk = testing::disk(16, MeshDensity::medium);
  const double turn = max_neighbour_shift(disk) / 2;
  const Eigen::VectorXd sigma = Eigen::VectorXd::Constant(disk.num_triangles(), 1.0);
  const Eigen::VectorXd nominal = ForwardModel(disk).measured(sigma);
  const Eigen::VectorXd together =
      ForwardModel(shift_electrodes(disk, std::vector<double>(16, turn))).measured(sigma);
  std::vector<double> one(16, 0.0);
  one[3] = turn;
  const Eigen::VectorXd alone = ForwardModel(shift_electrodes(disk, one)).measured(sigma);
  const double rotated = (together - nominal).norm() / nominal.norm();
  const double moved = (alone - nominal).norm() / nominal.norm();
  EXPECT_LT(rotated, 1e-4);
  EXPECT_GT(moved, 1000 * rotated);
}

TEST(ElectrodeShift, RefusesShiftsItCannotMake) {
  const Mesh& disk = testing::disk(16, MeshDensity::coarse);
  EXPECT_THROW(shift_electrodes(disk, std::vector<double>(15, 0.0)), InputError);
  std::vector<double> zigzag(16);
  for (int e = 0; e < 16; ++e) zigzag[e] = (e % 2 ? 0.6 : -0.6) * max_neighbour_shift(disk);
  try {
    shift_electrodes(disk, zigzag);
    ADD_FAILURE() << "neighbours apart by 1.2x the bound accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "--randomise-electrodes");
  }
  zigzag[0] = std::nan("");
  EXPECT_THROW(shift_electrodes(disk, zigzag), InputError);
}

}  // namespace
}  // namespace eitbench
