// eitbench calibrate --presses: how a press set's recorded positions lie on the electrodes and,
// with --out, the touch that explains its changes (the sensor fit), written into a sensor file.
#include <fmt/core.h>

#include "commands.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/measurements.h"
#include "eitbench/bench/data/press_touches.h"
#include "eitbench/bench/data/sensor.h"
#include "eitbench/bench/io/content_hash.h"
#include "eitbench/solvers.h"
#include "options.h"
#include "press_frame_command.h"

namespace eitbench::cli {
namespace {

// A press set with one touch a press, read for the fits, and the model on its protocol.
struct Presses {
  Dataset d;
  Eigen::MatrixX2d positions;
  Eigen::VectorXd depths;  // empty where the set records none
  std::shared_ptr<const ForwardModel> model;
};

// `forward`: the sensor's contact impedances and current (calibrated, or nominal); the protocol
// is the set's.
Presses read_presses(const Mesh& mesh, const std::string& path, ForwardOptions forward = {}) {
  Presses p{read_dataset(path), {}, {}, nullptr};
  const Dataset& d = p.d;
  check_press_set(path, d, measurement_protocol(d));  // one known touch a frame
  if (mesh.num_electrodes() != d.electrodes)
    throw InputError(
        path, "electrodes",
        fmt::format("{} electrodes; the mesh has {}", d.electrodes, mesh.num_electrodes()));
  p.positions.resize(d.size(), 2);
  if (d.touch_size == "depth") p.depths.resize(d.size());
  for (int i = 0; i < d.size(); ++i) {
    const PressTouch& t = d.touches[static_cast<std::size_t>(i)][0];
    p.positions.row(i) << t.x, t.y;
    if (p.depths.size() > 0) p.depths[i] = t.size;
  }
  if (p.depths.size() > 0 && !p.depths.allFinite()) p.depths.resize(0);  // not every depth known
  forward.protocol = std::make_shared<const MeasurementProtocol>(measurement_protocol(d));
  p.model = std::make_shared<const ForwardModel>(mesh, forward);
  return p;
}

PressFrame search_frame(const Presses& p, const LinearProblem& problem,
                        const PressFrameOptions& options, const std::string& path) {
  const PressFrame f = fit_press_frame(problem, p.d.differences, p.positions, options);
  fmt::print(
      "{}: {} presses fit best turned by {:g} degrees counter-clockwise{} (mean cosine {:.3f} "
      "between measured and modelled changes; the other handedness at best {:.3f}, turns 45 "
      "degrees or more away {:.3f})\n",
      path, p.d.size(), f.rotate_degrees, f.mirror ? ", mirrored first (y -> -y)" : "", f.cosine,
      f.other_mirror_cosine, f.other_turn_cosine);
  return f;
}

void print_how_to_apply(double rotate_degrees, bool mirror) {
  // Applied after the import's own turn b (and mirror): R(a) R(b) = R(a + b), R(a) M R(b) = R(a -
  // b) M.
  if (mirror)
    fmt::print(
        "  to apply it: import again with --touch-mirror toggled and --touch-rotate {:g} "
        "minus the turn used\n",
        rotate_degrees);
  else if (rotate_degrees != 0)
    fmt::print("  to apply it: import again with --touch-rotate {:g} plus the turn used\n",
               rotate_degrees);
}

}  // namespace

void print_press_frame(const Mesh& mesh, const std::string& path,
                       const PressFrameOptions& options) {
  const Presses p = read_presses(mesh, path);
  const LinearProblem problem = make_linear_problem(p.model, 1.0, PixelGrid(64, p.d.radius));
  const PressFrame f = search_frame(p, problem, options, path);
  print_how_to_apply(f.rotate_degrees, f.mirror);
}

SensorPressFit fit_press_sensor_file(const Mesh& mesh, const std::string& path,
                                     const PressFrameOptions& frame,
                                     const PressSensorOptions& options,
                                     const ForwardOptions& forward, double background) {
  const Presses p = read_presses(mesh, path, forward);
  const LinearProblem problem = make_linear_problem(p.model, background, PixelGrid(64, p.d.radius));
  const PressFrame start = search_frame(p, problem, frame, path);
  // The changes in the model's units, so that the contrast is on the label scale: the set's
  // reference fitted to the model's empty frame (no reference recorded: the frames as they are).
  const ReferenceCalibration gain = calibrate_to_model(
      p.d.reference,
      p.model->measured(Eigen::VectorXd::Constant(mesh.num_triangles(), problem.background)));
  const PressSensor s = fit_press_sensor(problem, p.d.differences * gain.scale, p.positions,
                                         p.depths, start, options);
  SensorPressFit f;
  f.presses = path;
  f.presses_hash = file_hash(path);
  f.rotate_degrees = s.rotate_degrees, f.mirror = s.mirror, f.scale = s.scale;
  f.touch_radius = s.touch_radius, f.contrast = s.contrast, f.per_depth = s.per_depth;
  f.gain = gain.scale;
  f.start_residual = s.start_residual, f.relative_residual = s.relative_residual;
  f.iterations = s.iterations, f.converged = s.converged;
  fmt::print(
      "  sensor fit: turned by {:.2f} degrees{}, positions x {:.4f}; the touch a disc of radius "
      "{:.4g} ({:.3f} R), contrast {:.4g}{}; residual {:.3f} of the changes (at the search's "
      "frame {:.3f}) after {} iterations{}\n",
      f.rotate_degrees, f.mirror ? " after the mirror" : "", f.scale, f.touch_radius,
      f.touch_radius / p.d.radius, f.contrast, f.per_depth ? " per unit depth" : " every press",
      f.relative_residual, f.start_residual, f.iterations, f.converged ? "" : " (NOT converged)");
  if (s.scale_at_bound || s.radius_at_bound)
    fmt::print(stderr,
               "warning: the {} ended on its bound: are the positions in the mesh's unit "
               "(import --touch-scale)?\n",
               s.scale_at_bound ? "scale" : "touch radius");
  if (std::isnan(gain.fit))
    fmt::print("  the set records no reference frame: its changes taken in the model's units\n");
  else
    fmt::print("  changes x {:.6g} to the model's units (its reference's cosine {:.4f})\n",
               gain.scale, gain.fit);
  return f;
}

}  // namespace eitbench::cli
