// eitbench calibrate --presses: how a press set's recorded positions lie on the electrodes.
#include <fmt/core.h>

#include "commands.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/sensor.h"
#include "eitbench/solvers.h"
#include "options.h"

namespace eitbench::cli {

void print_press_frame(const Mesh& mesh, const std::string& path,
                       const PressFrameOptions& options) {
  const Dataset d = read_dataset(path);
  if (d.touches.empty())
    throw InputError(path, "touches", "is not a press set (import --touches makes one)");
  if (mesh.num_electrodes() != d.electrodes)
    throw InputError(
        path, "electrodes",
        fmt::format("{} electrodes; the mesh has {}", d.electrodes, mesh.num_electrodes()));
  Eigen::MatrixX2d positions(d.size(), 2);
  for (int i = 0; i < d.size(); ++i) {
    const auto& list = d.touches[static_cast<std::size_t>(i)];
    if (list.size() != 1)
      throw InputError(path, "touches",
                       fmt::format("frame {} has {} touches; the fit takes one", i, list.size()));
    positions.row(i) << list[0].x, list[0].y;
  }
  ForwardOptions forward;
  forward.protocol = std::make_shared<const MeasurementProtocol>(measurement_protocol(d));
  const auto model = std::make_shared<const ForwardModel>(mesh, forward);
  const LinearProblem problem = make_linear_problem(model, 1.0, PixelGrid(64, d.radius));
  const PressFrame f = fit_press_frame(problem, d.differences, positions, options);
  fmt::print(
      "{}: {} presses fit best turned by {:g} degrees counter-clockwise{} (mean cosine {:.3f} "
      "between measured and modelled changes; the other handedness at best {:.3f}, turns 45 "
      "degrees or more away {:.3f})\n",
      path, d.size(), f.rotate_degrees, f.mirror ? ", mirrored first (y -> -y)" : "", f.cosine,
      f.other_mirror_cosine, f.other_turn_cosine);
  // Applied after the import's own turn b (and mirror): R(a) R(b) = R(a + b), R(a) M R(b) = R(a -
  // b) M.
  if (f.mirror)
    fmt::print(
        "  to apply it: import again with --touch-mirror toggled and --touch-rotate {:g} "
        "minus the turn used\n",
        f.rotate_degrees);
  else if (f.rotate_degrees != 0)
    fmt::print("  to apply it: import again with --touch-rotate {:g} plus the turn used\n",
               f.rotate_degrees);
}

}  // namespace eitbench::cli
