// eitbench calibrate: the background conductivity and each electrode's contact impedance fitted
// to a frame of the untouched sensor, and the frame and touch of a press set (--presses), written
// as a sensor file that forward, jacobian, reconstruct and run take with --sensor.
#include <fmt/core.h>

#include <memory>

#include "commands.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/measurements.h"
#include "eitbench/bench/data/sensor_noise.h"
#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/solvers/calibration.h"
#include "eitbench/solvers/press_frame.h"
#include "options.h"
#include "press_frame_command.h"

namespace eitbench::cli {

#ifdef EITBENCH_HAVE_CERES
namespace {

void print_calibration(const Calibration& c) {
  fmt::print(
      "background {:.6g} S/m; contact impedances {:.4g} .. {:.4g}; residual {:.3g} of the "
      "frame after {} iterations{}\n",
      c.background, c.contact_impedances.minCoeff(), c.contact_impedances.maxCoeff(),
      c.relative_residual, c.iterations, c.converged ? "" : " (NOT converged)");
}

// The background and the contact impedances fitted to the empty sensor's frame at `path`.
Calibration calibrate_reference(const Mesh& mesh, const std::string& path,
                                const std::string& variable, const std::string& order,
                                double background, double contact_impedance, double current) {
  ImportOptions io;
  io.electrodes = mesh.num_electrodes();
  io.order = order == "ascending" ? MeasurementOrder::ascending : MeasurementOrder::rotating;
  io.variable = variable;
  io.keep_maps = true;
  const Measurements m = read_measurements(path, io);
  // A map's pairs that touch a driven electrode carry the contact impedances; without them the
  // impedances are a guess the noise decides.
  const bool map = m.maps.size() > 0;
  const Eigen::VectorXd reference =
      (map ? m.maps : m.frames).colwise().mean().transpose();  // a map, or rotating order
  if (!map)
    fmt::print(stderr,
               "note: {} holds L(L-3) frames, which read no current-carrying electrode: the "
               "background is well determined, the contact impedances only noise-free. An L x L "
               "map (forward --values map) reads them.\n",
               path);
  ForwardOptions start;
  start.contact_impedance = contact_impedance;
  start.current = current;
  return calibrate(mesh, start, background, reference, MeasurementOrder::rotating, {}, path);
}

// The noise, drift, gains and signal size of the set at `path` (its frames `range`), measured on
// its paired references; the gains against the model of the sensor calibrated so far.
SensorNoise measure_noise(const Mesh& mesh, const std::string& path, const std::string& range,
                          const SensorFile& sensor) {
  const Dataset d = read_dataset(path);
  if (mesh.num_electrodes() != d.electrodes)
    throw InputError(
        path, "electrodes",
        fmt::format("{} electrodes; the mesh has {}", d.electrodes, mesh.num_electrodes()));
  const auto [first, last] = parse_range(range, d.size(), "--noise-frames");
  ForwardOptions forward;
  forward.contact_impedances = sensor.contact_impedances;
  forward.current = sensor.current;
  forward.protocol = std::make_shared<const MeasurementProtocol>(measurement_protocol(d));
  const ForwardModel model(mesh, forward);
  const Eigen::VectorXd empty =
      model.measured(Eigen::VectorXd::Constant(mesh.num_triangles(), sensor.background));
  const SensorNoise n = measure_sensor_noise(d, path, first, last, empty);
  fmt::print(
      "{}: {} references; a difference frame's noise {:.3g} of the reference's RMS, its "
      "signal {:.3g} (SNR {:.1f} dB); drift {:.3g}; channel gains against the model spread by "
      "{:.3g}\n",
      path, n.references, n.noise, n.signal, n.snr_db(), n.drift, n.gain_spread);
  return n;
}

}  // namespace

std::function<void()> add_calibrate_command(CLI::App& app) {
  struct Args {
    MeshSource mesh;
    std::string reference, variable, order = "rotating", out, presses, noise, noise_frames;
    double background = 1, contact_impedance = 0.01, current = 1;
    PressFrameOptions frame;
    PressSensorOptions fit;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "calibrate",
      "Fit the background conductivity and each electrode's contact impedance to the empty "
      "sensor's frame, and the frame and touch of labelled presses; write a sensor file "
      "(--sensor of forward, jacobian, reconstruct, run)");
  cmd->add_option("--reference", args->reference,
                  "the untouched sensor's frames, absolute voltages (.csv/.npy/.npz/.mat; the "
                  "mean of several): an L x L map of every adjacent pair (needed for the contact "
                  "impedances) or L(L-3) values");
  cmd->add_option("--presses", args->presses,
                  "a press set (import --touches): fit how its recorded positions lie on the "
                  "electrodes (the turn and the handedness that best explain its changes); with "
                  "--out also their scale and the touch (a disc's radius and contrast, per unit "
                  "depth where the set records depths), written into the sensor file");
  cmd->add_option("--noise", args->noise,
                  "a measured set with a reference recorded before each frame (import "
                  "--paired-reference; positions not needed): measure the sensor's noise, drift, "
                  "channel gains and signal size on it, and write them into the sensor file "
                  "(reconstruct --choose discrepancy uses the noise)");
  cmd->add_option("--noise-frames", args->noise_frames,
                  "--noise: frames A:B of the set (default all), e.g. those a scored part does "
                  "not hold");
  cmd->add_option("--step", args->frame.step_degrees, "--presses: the turns tried, in degrees")
      ->capture_default_str();
  cmd->add_option("--touch-radius", args->frame.touch_radius,
                  "--presses: each press drawn as a disc of this radius (x R)")
      ->capture_default_str();
  cmd->add_option("--huber", args->fit.huber,
                  "--presses --out: a Huber loss on each press's misfit beyond this (relative to "
                  "the set's; 0: least squares)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--variable", args->variable, "array or variable in --reference");
  cmd->add_option("--order", args->order, "order of L(L-3)-value frames")
      ->capture_default_str()
      ->check(CLI::IsMember({"rotating", "ascending"}));
  add_mesh_options(*cmd, args->mesh);
  cmd->add_option("--background", args->background, "the start: conductivity (S/m)")
      ->capture_default_str()
      ->check(kPositive);
  cmd->add_option("--contact-impedance", args->contact_impedance,
                  "the start: every electrode's contact impedance")
      ->capture_default_str()
      ->check(kPositive);
  cmd->add_option("--current", args->current, "the drive current the frame was measured with")
      ->capture_default_str();
  cmd->add_option("--out", args->out,
                  "the sensor file to write (JSON): with --reference its background and contact "
                  "impedances, with --presses the press fit, with --noise the noise (without "
                  "--reference, the nominal --background and --contact-impedance, marked as not "
                  "fitted)");
  return [args] {
    const Mesh mesh = load_mesh(args->mesh);
    if (args->reference.empty() && args->presses.empty() && args->noise.empty())
      throw InputError("calibrate", "",
                       "needs --reference (the empty sensor's frame), --presses (a press set) or "
                       "--noise (a set with paired references)");
    if (!args->noise_frames.empty() && args->noise.empty())
      throw InputError("--noise-frames", "", "needs --noise, the set whose frames it selects");
    if (!args->presses.empty() && args->out.empty()) {
      print_press_frame(mesh, args->presses, args->frame);
      if (args->reference.empty() && args->noise.empty()) return;
    }
    if (args->out.empty() && !args->noise.empty() && args->reference.empty()) {
      SensorFile nominal;
      nominal.current = args->current, nominal.background = args->background;
      nominal.contact_impedances =
          Eigen::VectorXd::Constant(mesh.num_electrodes(), args->contact_impedance);
      measure_noise(mesh, args->noise, args->noise_frames, nominal);
      return;
    }
    if (args->out.empty())
      throw InputError("--out", "", "--reference needs --out, the sensor file to write");
    SensorFile s;
    s.electrodes = mesh.num_electrodes();
    s.current = args->current;
    if (args->reference.empty()) {  // the press fit alone: nominal values, marked as such
      s.background = args->background;
      s.contact_impedances = Eigen::VectorXd::Constant(s.electrodes, args->contact_impedance);
      s.fitted = false;
    } else {
      const Calibration c =
          calibrate_reference(mesh, args->reference, args->variable, args->order, args->background,
                              args->contact_impedance, args->current);
      s.background = c.background;
      s.contact_impedances = c.contact_impedances;
      s.reference = args->reference;
      s.relative_residual = c.relative_residual;
      s.iterations = c.iterations;
      s.converged = c.converged;
      print_calibration(c);
    }
    if (!args->presses.empty()) {  // on the sensor just calibrated (or the nominal one)
      ForwardOptions forward;
      forward.contact_impedances = s.contact_impedances;
      forward.current = s.current;
      s.press_fit =
          fit_press_sensor_file(mesh, args->presses, args->frame, args->fit, forward, s.background);
    }
    if (!args->noise.empty()) s.noise = measure_noise(mesh, args->noise, args->noise_frames, s);
    write_sensor_file(args->out, s);
    fmt::print("wrote {}\n", args->out);
  };
}
#else
std::function<void()> add_calibrate_command(CLI::App& app) {
  app.add_subcommand("calibrate", "(this build has no Ceres: no calibration)");
  return [] { throw InputError("calibrate", "", "this build has no Ceres (EITBENCH_WITH_CERES)"); };
}
#endif

}  // namespace eitbench::cli
