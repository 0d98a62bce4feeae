// Stage 1: the data, simulated for the preset or the user's, and the frames every later stage uses.
#include <fmt/core.h>

#include <cmath>

#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/press_touches.h"
#include "eitbench/bench/data/sensor.h"
#include "eitbench/bench/data/simulate.h"
#include "eitbench/bench/support/progress.h"
#include "eitbench/bench/support/version.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/msh_io.h"
#include "stages.h"

namespace eitbench::run {
namespace fs = std::filesystem;
namespace {

FrameSet rows_of(const Dataset& d, const std::vector<int>& rows) {
  FrameSet f;
  f.frames.resize(static_cast<Eigen::Index>(rows.size()), d.differences.cols());
  f.labels.resize(static_cast<Eigen::Index>(rows.size()), d.labels.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    f.frames.row(k) = d.differences.row(rows[k]);
    if (d.has_labels()) f.labels.row(k) = d.labels.row(rows[k]);
    if (!d.circles.empty()) f.circles.push_back(d.circles[static_cast<std::size_t>(rows[k])]);
  }
  return f;
}

MeasurementProtocol config_protocol(const RunConfig& config, int electrodes) {
  return make_protocol(config.protocol, electrodes).with_magnitude(config.magnitude);
}

std::string sensor_name(const RunConfig& config) {
  return fs::path(config.mesh_file).filename().string();
}

// What a simulated set must be to serve this run: "" when `d` is it, else the differences.
// The protocol the preset's set is simulated on: the user's data's when the run has data (the
// training source must read frames as the test frames are read), else --protocol's.
MeasurementProtocol simulation_protocol(const RunConfig& config, int electrodes,
                                        const MeasurementProtocol* data_protocol) {
  return data_protocol ? *data_protocol : config_protocol(config, electrodes);
}

std::string simulation_differs(const Dataset& d, const RunConfig& config,
                               const MeasurementProtocol* data_protocol) {
  const std::string mesh =
      config.mesh_file.empty()
          ? "disk L=" + std::to_string(config.electrodes) + " " + to_string(config.simulation)
          : sensor_name(config) + ", refined once";
  std::string diff;
  auto differs = [&](const std::string& what, const std::string& has, const std::string& asked) {
    if (has != asked)
      diff += fmt::format("{}{} {} (this run: {})", diff.empty() ? "" : ", ", what, has, asked);
  };
  differs("preset", d.preset, config.preset);
  differs("seed", std::to_string(d.seed), std::to_string(config.seed));
  differs("simulation mesh", d.simulation_mesh, with_variation(mesh, config.variation));
  differs("program", d.program, program_version());
  const MeasurementProtocol wanted = simulation_protocol(config, d.electrodes, data_protocol);
  differs("protocol", measurement_protocol(d).name() + (d.magnitude ? " (magnitudes)" : ""),
          wanted.name() + (wanted.magnitude() ? " (magnitudes)" : ""));
  if (!measurement_protocol(d).same_channels(wanted))
    diff += fmt::format("{}protocol channels", diff.empty() ? "" : ", ");
  if (!config.mesh_file.empty() && d.sensor_mesh != mesh_text(read_msh_file(config.mesh_file)))
    diff += fmt::format("{}sensor mesh (this run: {}'s as it is now)", diff.empty() ? "" : ", ",
                        config.mesh_file);
  return diff;
}

// The preset's simulated set in <out>/data.h5. A resumed run reads it back, and stops when it is
// not the set this run would simulate: every finished stage of the folder was made from it.
Dataset simulated(const Context& context, const MeasurementProtocol* data_protocol = nullptr) {
  const RunConfig& config = context.config;
  const std::string path = (context.out / "data.h5").string();
  if (config.resume && fs::exists(path)) {
    Dataset d = read_dataset(path);
    if (const std::string diff = simulation_differs(d, config, data_protocol); !diff.empty())
      throw InputError(path, "",
                       "holds another data set than this run asks for: " + diff +
                           ". --resume continues a run on the same data: choose a new --out, "
                           "or leave out --resume to start this folder afresh");
    context.say(fmt::format("data: {} samples from {} (resumed)", d.size(), path));
    return d;
  }
  SimulationOptions s;
  s.preset = config.preset;
  s.seed = config.seed;
  s.density = config.simulation;
  s.electrodes = config.electrodes;
  s.variation = config.variation;
  if (!config.mesh_file.empty()) {
    s.sensor_mesh = std::make_shared<const Mesh>(read_msh_file(config.mesh_file));
    s.sensor_source = sensor_name(config);
  }
  s.protocol = std::make_shared<const MeasurementProtocol>(simulation_protocol(
      config, s.sensor_mesh ? s.sensor_mesh->num_electrodes() : config.electrodes, data_protocol));
  const auto counts = preset_counts(config.preset);
  int total = 0;
  for (int c : counts.circles) total += c;
  context.say(
      fmt::format("data: simulating the {} preset ({} samples, seed {}, {} protocol{}, "
                  "{} mesh)",
                  config.preset, total, config.seed, s.protocol->name(),
                  s.protocol->magnitude() ? ", magnitudes" : "",
                  config.mesh_file.empty() ? to_string(config.simulation)
                                           : config.mesh_file + " refined once"));
  Progress progress("simulate", total, config.quiet);
  Dataset d = simulate_dataset(s, [&](int done, int) { progress.update(done); });
  write_dataset(path, d);
  return d;
}

// The user's data: an eitbench data set, or measured frames (with their reference) to import.
Dataset users(const RunConfig& config) {
  if (is_hdf5_file(config.data) && config.reference.empty()) {
    Dataset d = read_dataset(config.data);
    // A set carries its protocol: --protocol and --magnitude may only confirm it.
    const bool chosen = config.protocol != "adjacent" || config.magnitude;
    if (chosen && !measurement_protocol(d).same_channels(config_protocol(config, d.electrodes)))
      throw InputError(config.protocol != "adjacent" ? "--protocol" : "--magnitude", "",
                       config.data + " is read on the " + measurement_protocol(d).name() +
                           " protocol" + (d.magnitude ? " (magnitudes)" : "") +
                           ": leave out --protocol and --magnitude to use the set's own");
    return d;
  }
  ImportOptions o;
  o.electrodes = config.electrodes;
  if (config.protocol != "adjacent" || config.magnitude)
    o.protocol =
        std::make_shared<const MeasurementProtocol>(config_protocol(config, config.electrodes));
  return import_measurements(config.data, config.reference, o);
}

// Frames evaluated against a simulated source must come from its sensor; they are brought to its
// units by their reference frame.
void calibrate_to_source(const Context& context, RunData& r) {
  const RunConfig& config = context.config;
  if (r.data.electrodes != r.source.electrodes)
    throw InputError(config.data, "electrodes",
                     fmt::format("{} electrodes, but the preset simulates {}: pass --electrodes {}",
                                 r.data.electrodes, r.source.electrodes, r.data.electrodes));
  if (r.labelled && r.data.image_size != r.source.image_size)
    throw InputError(
        config.data, "image_size",
        fmt::format("{}×{} labels, but the preset's images are {}×{}", r.data.image_size,
                    r.data.image_size, r.source.image_size, r.source.image_size));
  if (!measurement_protocol(r.data).same_channels(measurement_protocol(r.source)))
    throw InputError(config.data, "protocol",
                     "is read on the " + measurement_protocol(r.data).name() +
                         " protocol, the simulated source on " +
                         measurement_protocol(r.source).name());
  r.calibration = calibrate_to_model(r.data.reference, r.source.reference);
  r.test.frames *= r.calibration.scale;
  context.say("calibration: " + describe(r.calibration));
  if (r.calibration.fit < 0.95)
    context.say(
        "warning: the reference frame fits the model's poorly; check --electrodes and the "
        "measurement order (--order of eitbench import)");
}

// What every stage's results depend on, besides its own settings.
Provenance common_provenance(const RunConfig& config, const RunData& r) {
  std::string snrs;
  for (double v : r.snrs) snrs += (snrs.empty() ? "" : " ") + fmt::format("{:g}", v);
  return {{"program", program_version()},
          {"data", content_hash(r.data)},
          {"training data", r.own_training ? "the data" : content_hash(r.source)},
          {"sensor", file_hash(config.sensor)},
          {"mesh", to_string(config.mesh)},
          {"snrs", snrs},
          {"seed", std::to_string(config.seed)},
          {"threads", std::to_string(config.threads)},
          {"timed frames", std::to_string(config.timed_frames)},
          {"sweep frames", std::to_string(config.sweep_frames)},
          {"touch validation frames", std::to_string(config.touch_validation_frames)},
          {"figure samples", std::to_string(config.figure_samples)}};
}

}  // namespace

std::string describe(const ReferenceCalibration& c) {
  return std::isnan(c.fit)
             ? "none (no reference frame: the frames are taken as differences in the preset's "
               "units)"
             : fmt::format(
                   "frames × {:.6g}, the least-squares fit of the data's reference frame "
                   "to the simulated preset's (cosine {:.6f})",
                   c.scale, c.fit);
}

RunData load_data(const Context& context) {
  const RunConfig& config = context.config;
  RunData r;
  if (config.data.empty() && !config.measured.empty()) {
    // Real presses: the preset simulated on the measured set's board, the presses scored after
    // the simulated stages (measured_stage.cpp).
    const Dataset presses = read_dataset(config.measured);
    if (presses.electrodes != config.electrodes)
      throw InputError(config.measured, "electrodes",
                       fmt::format("{} electrodes; pass --electrodes {} to simulate them",
                                   presses.electrodes, presses.electrodes));
    const MeasurementProtocol protocol = measurement_protocol(presses);
    // Both sets are checked before the simulated stages, so that a wrong file costs nothing.
    check_press_set(config.measured, presses, protocol);
    check_press_set(config.press_calibration, read_dataset(config.press_calibration), protocol);
    sensor_press_fit(config);
    r.data = simulated(context, &protocol);
    r.data_path = (context.out / "data.h5").string();
  } else if (config.data.empty()) {
    r.data = simulated(context);
    r.data_path = (context.out / "data.h5").string();
  } else {
    r.data = users(config);
    r.data_path = config.data;
    context.say(fmt::format("data: {} frames from {}{}", r.data.size(), config.data,
                            r.data.has_labels() ? "" : " (no labels: images and speed only)"));
  }
  r.own_training = r.data.has_labels() && !r.data.indices(Split::train).empty() &&
                   !r.data.indices(Split::validation).empty();
  if (r.own_training) {
    r.source = r.data;
  } else if (has_sensor_mesh(r.data)) {
    // The simulated preset is the disk's (or --mesh's): its grid and model are not this sensor's.
    throw InputError(config.data, "split",
                     "a set on a sensor of another shape needs its own train and validation "
                     "splits; simulate them on its mesh (run --mesh, or simulate --mesh)");
  } else {
    r.labelled = r.data.has_labels();
    context.say(
        "training and hyperparameters: the simulated preset (the data have no labelled "
        "train/validation splits)");
    const MeasurementProtocol data_protocol = measurement_protocol(r.data);
    r.source = simulated(context, &data_protocol);
  }
  std::vector<int> test_rows = r.data.indices(Split::test);
  if (test_rows.empty() && !r.data.has_labels())  // measured frames: all of them
    for (int i = 0; i < r.data.size(); ++i) test_rows.push_back(i);
  if (test_rows.empty()) throw InputError(config.data, "split", "no test frames to evaluate");
  r.test = rows_of(r.data, test_rows);
  r.validation = rows_of(r.source, r.source.indices(Split::validation));
  if (!r.own_training) calibrate_to_source(context, r);
  // Measured frames carry their own noise: they are evaluated as they are.
  r.snrs = r.data.preset == "imported" ? std::vector<double>{INFINITY} : config.snrs;
  r.provenance = common_provenance(config, r);
  return r;
}

}  // namespace eitbench::run
