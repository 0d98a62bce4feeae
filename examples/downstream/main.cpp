// The forward model and a one-step reconstruction from an installed eitbench: a touch's frame on
// the built-in disk, and its NOSER image's correlation with the touch.
#include <cstdio>

#include "eitbench/jacobian.h"
#include "eitbench/solvers.h"

int main() {
  using namespace eitbench;
  auto model = std::make_shared<const ForwardModel>(generate_disk_mesh({16, MeshDensity::coarse}));
  const PixelGrid grid(32, 1.0);
  auto problem = std::make_shared<const LinearProblem>(make_linear_problem(model, 1.0, grid));
  const Eigen::VectorXd touch = circles_image(grid, {{0.4, 0.2, 0.2, 0.5}}, 1.0);
  const Eigen::VectorXd frame = problem->A * problem->from_image(touch);
  TikhonovOptions options;
  options.prior = Prior::noser;
  const Eigen::VectorXd image = Tikhonov(problem, options).reconstruct(frame);
  // Pearson's correlation over the pixels inside the disk.
  const auto inside = grid.mask();
  Eigen::VectorXd a(inside.count()), b(inside.count());
  for (Eigen::Index i = 0, k = 0; i < image.size(); ++i)
    if (inside[i]) a[k] = image[i], b[k++] = touch[i];
  a.array() -= a.mean(), b.array() -= b.mean();
  const double cc = a.dot(b) / (a.norm() * b.norm());
  std::printf("frame of %d values, NOSER image CC %.3f\n", static_cast<int>(frame.size()), cc);
  return cc > 0.5 ? 0 : 1;
}
