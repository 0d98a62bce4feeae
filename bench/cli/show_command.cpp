// eitbench show: one sample of a data set as a picture: its label over the reconstruction mesh's
// rim and electrodes, and its voltage profile.
#include <fmt/core.h>

#include <memory>

#include "commands.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/sensor.h"
#include "eitbench/bench/report/figures.h"
#include "eitbench/jacobian.h"
#include "options.h"

namespace eitbench::cli {

std::function<void()> add_show_command(CLI::App& app) {
  struct Args {
    std::string file, out;
    int index = 0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "show", "Draw one sample: label, mesh outline with electrodes, voltage profile (PNG)");
  cmd->add_option("file", args->file, "an eitbench HDF5 data set")->required();
  cmd->add_option("--index", args->index, "sample index (0-based)")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd->add_option("--out", args->out, "PNG file to write")->required();
  return [args] {
    const Dataset d = read_dataset(args->file);
    if (args->index >= d.size())
      throw InputError("--index", "",
                       std::to_string(args->index) + " is past the last sample (" +
                           std::to_string(d.size() - 1) + ")");
    const int i = args->index;
    // The disk at the medium density, or the sensor mesh the set stores, and its labels' grid.
    const Mesh outline = reconstruction_mesh(d, MeshDensity::medium);
    const PixelGrid grid = image_grid(d);
    SampleFigure f;
    f.title =
        fmt::format("{} sample {} ({}{})", args->file, i, to_string(d.split[i]),
                    d.circles.empty() ? "" : fmt::format(", {} circles", d.circles[i].size()));
    f.image = d.has_labels() ? Eigen::VectorXd(d.labels.row(i).transpose())
                             : Eigen::VectorXd::Constant(grid.num_pixels(),
                                                         std::numeric_limits<double>::quiet_NaN());
    f.mask = grid.mask();
    f.image_min = 0;
    f.image_max = 1;
    f.outline = &outline;
    f.radius = d.radius;
    const MeasurementProtocol protocol = measurement_protocol(d);
    f.plot_title = "difference voltages (the " + protocol.name() + " protocol's inputs)";
    f.x_label = protocol.reciprocal() ? "input (one of each reciprocal pair)" : "channel";
    f.y_label = "dv (V)";
    const Eigen::VectorXd dv = d.differences.row(i).transpose();
    PlotSeries series;
    series.y.assign(dv.data(), dv.data() + dv.size()), series.label = "dv";
    f.series.push_back(series);
    draw_sample_png(f, args->out);
    fmt::print("wrote {}\n", args->out);
  };
}

}  // namespace eitbench::cli
