// eitbench import: measured frames (CSV, NPY/NPZ, MAT) and a reference to an eitbench data set.
#include <fmt/core.h>

#include <memory>

#include "commands.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/measurements.h"
#include "eitbench/bench/data/press_touches.h"
#include "options.h"

namespace eitbench::cli {
namespace {

// Frames [a, b) of `d`, with what belongs to each frame; paired references give the reference
// again as the mean of those kept (a single reference file's mean stays, and so does the mean
// that --relative changes are in the units of).
void keep_frames(Dataset& d, std::pair<int, int> range, bool relative) {
  const auto [a, b] = range;
  const Eigen::Index n = b - a;
  d.frames = SampleMatrix(d.frames.middleRows(a, n));
  d.differences = SampleMatrix(d.differences.middleRows(a, n));
  if (d.references.rows() > 0) {
    d.references = SampleMatrix(d.references.middleRows(a, n));
    if (!relative) d.reference = d.references.colwise().mean().transpose();
  }
  if (!d.touches.empty()) d.touches = {d.touches.begin() + a, d.touches.begin() + b};
  d.split.assign(static_cast<std::size_t>(n), Split::test);
}

}  // namespace

void add_import_options(CLI::App& cmd, ImportOptions& o, std::string& order,
                        ProtocolChoice& protocol) {
  cmd.add_option("--electrodes", o.electrodes, "electrodes L")
      ->capture_default_str()
      ->check(CLI::Range(4, 256));
  cmd.add_option("--order", order, "order of L(L-3)-value frames: rotating | ascending")
      ->capture_default_str()
      ->check(CLI::IsMember({"rotating", "ascending"}));
  cmd.add_option("--variable", o.variable, "array (.npz) or variable (.mat) holding the frames");
  add_protocol_options(cmd, protocol);
}

std::function<void()> add_import_command(CLI::App& app) {
  struct Args {
    ImportOptions options;
    std::string in, reference, reference_variable, order = "rotating", out;
    ProtocolChoice protocol;
    TouchFileOptions touches;
    double radius = 1;
    std::string frames;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "import", "Measured frames and a reference frame to an eitbench HDF5 data set");
  cmd->add_option("--in", args->in, "frames: .csv, .npy, .npz or .mat (v5 or v7.3)")->required();
  cmd->add_option("--reference", args->reference,
                  "the empty sensor's frame(s), any of the same formats (mean if several)");
  cmd->add_option("--reference-variable", args->reference_variable,
                  "array or variable in --reference");
  cmd->add_flag("--paired-reference", args->options.paired_reference,
                "--reference holds one frame per frame (a reference recorded before every "
                "press): each frame minus its own");
  cmd->add_flag(
      "--relative", args->options.relative,
      "each change relative to its own reference, (v - v_ref) / v_ref, times the mean "
      "reference (voltage units; with --paired-reference each reference's gain divides out)");
  add_import_options(*cmd, args->options, args->order, args->protocol);
  cmd->add_option("--touches", args->touches.path,
                  "a press set: where each frame was pressed, a row a frame (x, y or x, y, size; "
                  ".csv, .npy, .npz or .mat)");
  cmd->add_option("--touch-variable", args->touches.variable,
                  "array or variable in --touches (default: the only numeric one, else touches, "
                  "positions or xy)");
  cmd->add_option("--touch-scale", args->touches.scale,
                  "multiplies the touches' lengths, from the file's unit to the mesh's (metres "
                  "on a unit disk of 70 mm: 14.2857)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--touch-size", args->touches.size,
                  "what a third column of --touches holds: depth (of the press) | radius (of "
                  "the probe)")
      ->check(CLI::IsMember({"depth", "radius"}));
  cmd->add_option("--touch-rotate", args->touches.rotate_degrees,
                  "turns the touches counter-clockwise by this many degrees, after scaling: the "
                  "file's frame to the mesh's, whose electrode 0 lies on +x (electrode 0 at 282 "
                  "degrees in the file: -282)");
  cmd->add_flag("--touch-mirror", args->touches.mirror,
                "y -> -y before turning: electrodes numbered clockwise in the file's frame");
  cmd->add_option("--radius", args->radius,
                  "the sensor's radius in the mesh's unit, recorded in the set; touches must lie "
                  "within it")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--frames", args->frames,
                  "keep frames A:B of the file (0-based, B excluded), with their references and "
                  "touches: a recording split by time, the earlier part to tune on, the later "
                  "one to score");
  cmd->add_option("--out", args->out, "HDF5 data set to write (all frames in the test split)")
      ->required();
  return [args] {
    args->options.order = parse_order(args->order);
    args->options.protocol = chosen_protocol(args->protocol, args->options.electrodes);
    const Measurements m = read_measurements(args->in, args->options);
    Dataset d = import_measurements(m, args->reference, args->options, args->reference_variable);
    d.radius = args->radius;
    fmt::print("{}: {}\n", args->in, m.description);
    if (!args->touches.path.empty()) {
      PressTruth truth = read_touch_file(args->touches, d.size(), d.radius);
      d.touches = std::move(truth.touches), d.touch_size = truth.size;
      fmt::print("  touches: one a frame from {}{}\n", args->touches.path,
                 d.touch_size.empty() ? "" : " (third column: " + d.touch_size + ")");
    }
    if (!args->frames.empty())
      keep_frames(d, parse_range(args->frames, d.size()), args->options.relative);
    if (m.reduced_input)
      fmt::print("  reciprocity: not measured ({})\n",
                 args->options.protocol && !is_adjacent(*args->options.protocol)
                     ? "frames in the protocol's own channels"
                     : "reduced frames are reciprocal by construction");
    else
      fmt::print("  reciprocity error: {:.3e} (mean relative |v(d,m) - v(m,d)| over the frames)\n",
                 m.reciprocity_error);
    if (args->reference.empty())
      fmt::print("  no --reference: the frames are taken to be differences already\n");
    if (const int same = frames_without_change(d))
      fmt::print(stderr, "warning: {} of {} frames equal the reference (no change anywhere)\n",
                 same, d.size());
    write_dataset(args->out, d);
    fmt::print("wrote {} ({} frames)\n", args->out, d.size());
  };
}

}  // namespace eitbench::cli
