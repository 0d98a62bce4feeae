// eitbench info: what a data file holds.
#include <fmt/core.h>

#include <cmath>

#include <memory>

#include "commands.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/measurements.h"
#include "eitbench/jacobian/protocol.h"
#include "options.h"

namespace eitbench::cli {

// A press set's truth: how many touches, where they lie, and their sizes.
void print_touches(const Dataset& d) {
  int count[5] = {0, 0, 0, 0, 0}, sized = 0;
  double reach = 0, low = INFINITY, high = -INFINITY;
  for (const auto& list : d.touches) {
    ++count[std::min<std::size_t>(list.size(), 4)];
    for (const PressTouch& t : list) {
      reach = std::max(reach, std::hypot(t.x, t.y));
      if (std::isnan(t.size)) continue;
      ++sized, low = std::min(low, t.size), high = std::max(high, t.size);
    }
  }
  fmt::print(
      "  touches (a press set): {} / {} / {} / {} / {} frames with 0 / 1 / 2 / 3 / 4, "
      "centres within {:.3g} of the middle (radius {:g})\n",
      count[0], count[1], count[2], count[3], count[4], reach, d.radius);
  if (sized > 0) fmt::print("  touch {}: {:.4g} .. {:.4g}\n", d.touch_size, low, high);
}

void print_dataset_summary(const std::string& path, const Dataset& d) {
  fmt::print("{}: eitbench data set, {} samples\n", path, d.size());
  if (!d.shard.whole())
    fmt::print("  shard {} of {}: rows {} to {} of the set's {} (eitbench merge joins them)\n",
               d.shard.index, d.shard.count, d.shard.first, d.shard.first + d.size() - 1,
               d.shard.total);
  fmt::print("  splits: train {}, validation {}, test {}\n", d.indices(Split::train).size(),
             d.indices(Split::validation).size(), d.indices(Split::test).size());
  fmt::print(
      "  sensor: {} electrodes, radius {}, background {} S/m, contact impedance {}, current {}\n",
      d.electrodes, d.radius, d.background, d.contact_impedance, d.current);
  fmt::print("  made by: {} (preset '{}', seed {}), {} ({} triangles)\n",
             d.program.empty() ? "?" : d.program, d.preset, d.seed, d.simulation_mesh,
             d.simulation_triangles);
  if (!d.sensor_mesh.empty())
    fmt::print("  sensor mesh: stored in the set ({} bytes of Gmsh text), symmetry group {}\n",
               d.sensor_mesh.size(), d.sensor_group);
  const MeasurementProtocol protocol = measurement_protocol(d);
  fmt::print("  protocol: {}{}, {} channels, {} inputs ({})\n", protocol.name(),
             protocol.magnitude() ? " (magnitudes |v|)" : "", protocol.size(),
             protocol.input_size(),
             protocol.reciprocal() ? "reciprocity-reduced" : "not reciprocal: every channel");
  fmt::print(
      "  frames: {} values; differences: {} values (the inputs), |dv| max {:.4g}, mean {:.4g}\n",
      d.frames.cols(), d.differences.cols(), d.differences.cwiseAbs().maxCoeff(),
      d.differences.cwiseAbs().mean());
  if (protocol.same_channels(adjacent_protocol(d.electrodes)))  // rotating, signed
    fmt::print("  reference: |v| max {:.4g}, reciprocity error {:.2e}\n",
               d.reference.cwiseAbs().maxCoeff(),
               Protocol(d.electrodes).reciprocity_error(d.reference, MeasurementOrder::rotating));
  else
    fmt::print("  reference: |v| max {:.4g}\n", d.reference.cwiseAbs().maxCoeff());
  if (d.references.rows() > 0)
    fmt::print("  paired references: one before each frame (calibrate --noise measures on them)\n");
  if (d.has_labels())
    fmt::print("  labels: {} x {} images, intensity {:.3f} .. {:.3f}\n", d.image_size, d.image_size,
               d.labels.minCoeff(), d.labels.maxCoeff());
  if (!d.circles.empty()) {
    int count[5] = {0, 0, 0, 0, 0};
    for (const auto& c : d.circles) ++count[std::min<std::size_t>(c.size(), 4)];
    fmt::print("  circles: {} / {} / {} / {} samples with 1 / 2 / 3 / 4\n", count[1], count[2],
               count[3], count[4]);
  }
  if (!d.touches.empty()) print_touches(d);
}

void add_import_options(CLI::App& cmd, ImportOptions& o, std::string& order,
                        ProtocolChoice& protocol);  // import_command.cpp

std::function<void()> add_info_command(CLI::App& app) {
  struct Args {
    std::string path, order = "rotating";
    ImportOptions options;
    ProtocolChoice protocol;
  };
  auto args = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("info", "Summarise a data file: an eitbench data set, or measured frames");
  cmd->add_option("file", args->path,
                  "an eitbench .h5 data set, or frames in .csv, .npy, .npz, .mat")
      ->required();
  add_import_options(*cmd, args->options, args->order, args->protocol);
  return [args] {
    const bool matlab =
        args->path.size() > 4 && args->path.compare(args->path.size() - 4, 4, ".mat") == 0;
    if (is_hdf5_file(args->path) && !matlab) {
      const Dataset d = read_dataset_or_shard(args->path);
      check_protocol_of(args->protocol, measurement_protocol(d), args->path);
      return print_dataset_summary(args->path, d);
    }
    args->options.order = parse_order(args->order);
    args->options.protocol = chosen_protocol(args->protocol, args->options.electrodes);
    const Measurements m = read_measurements(args->path, args->options);
    fmt::print("{}: {}\n", args->path, m.description);
    fmt::print("  |v| max {:.4g}, mean {:.4g}\n", m.frames.cwiseAbs().maxCoeff(),
               m.frames.cwiseAbs().mean());
    if (!m.reduced_input) fmt::print("  reciprocity error: {:.3e}\n", m.reciprocity_error);
  };
}

}  // namespace eitbench::cli
