// eitbench jacobian: the sensitivity matrix on elements or on the 64x64 pixel grid.
#include <fmt/core.h>

#include <filesystem>
#include <memory>

#include "commands.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/csv.h"
#include "eitbench/bench/io/hdf5_matrix.h"
#include "eitbench/bench/support/version.h"
#include "options.h"

namespace eitbench::cli {

std::function<void()> add_jacobian_command(CLI::App& app) {
  struct Args {
    MeshSource mesh;
    ConductivitySource sigma;
    ModelSetup model;
    ProtocolChoice protocol;
    std::string basis = "elements", out;
    int pixels = 64;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("jacobian",
                                 "The Jacobian dv/dsigma (adjoint method) on elements or pixels");
  add_mesh_options(*cmd, args->mesh);
  add_conductivity_options(*cmd, args->sigma);
  add_model_options(*cmd, args->model);
  cmd->add_option("--basis", args->basis, "elements | pixels")
      ->capture_default_str()
      ->check(CLI::IsMember({"elements", "pixels"}));
  cmd->add_option("--pixels", args->pixels, "image size N of the N x N pixel basis")
      ->capture_default_str()
      ->check(CLI::Range(4, 1024));
  add_protocol_options(*cmd, args->protocol);
  cmd->add_option("--out", args->out, "HDF5 (.h5, .hdf5) or CSV (.csv): one row per measurement")
      ->required();
  return [args, cmd] {
    const std::string extension = std::filesystem::path(args->out).extension().string();
    if (extension != ".csv" && extension != ".h5" && extension != ".hdf5")
      throw InputError("--out", "", "'" + args->out + "' must end in .h5, .hdf5 or .csv");
    const Mesh mesh = load_mesh(args->mesh);
    apply_sensor(args->model, mesh);
    const Eigen::VectorXd sigma = load_conductivity(*cmd, args->sigma, mesh);
    const bool reduced = reduced_values(args->model, mesh.num_electrodes());
    const MeasurementOrder order = parse_order(args->model.order);
    args->model.forward.protocol = chosen_protocol(args->protocol, mesh.num_electrodes());
    const ForwardModel model(mesh, args->model.forward,
                             args->mesh.file.empty() ? "mesh" : args->mesh.file);
    const MeasurementProtocol& protocol = model.measurement_protocol();
    const bool other = args->model.forward.protocol != nullptr;
    if (other && args->model.values != "full" && args->model.values != "reduced")
      throw InputError("--values", "",
                       "with --protocol: full (every channel) or reduced (the inputs)");
    const std::vector<Channel> rows = reduced ? protocol.input_channels() : protocol.channels();
    Eigen::MatrixXd J = other ? model.measured_jacobian(model.solve(sigma), rows)
                              : model.protocol().select_rows(model.jacobian(sigma), order, reduced);
    const bool pixels = args->basis == "pixels";
    const double radius = mesh.nodes.rowwise().norm().maxCoeff();
    if (pixels) J = J * pixel_to_element(mesh, PixelGrid(args->pixels, radius));
    if (extension == ".csv") {
      write_matrix_csv(args->out, J);
    } else {
      Hdf5Matrix content;
      content.name = "jacobian";
      content.matrix = &J;
      content.text_attributes = {{"basis", args->basis},
                                 {"order", reduced ? "reduced" : args->model.order},
                                 {"program", program_version()},
                                 {"mesh", args->mesh.file.empty() ? "generated" : args->mesh.file}};
      if (!args->model.sensor.empty()) content.text_attributes["sensor"] = args->model.sensor;
      content.number_attributes = {{"electrodes", double(mesh.num_electrodes())},
                                   {"triangles", double(mesh.num_triangles())},
                                   {"current", args->model.forward.current},
                                   {"contact_impedance", args->model.forward.contact_impedance}};
      if (pixels)
        content.number_attributes.insert({{"pixels", double(args->pixels)}, {"radius", radius}});
      if (other) {  // each row's channel: drive+, drive-, meas+, meas-
        content.text_attributes["protocol"] = protocol.name();
        content.table_name = "channels";
        content.table.resize(static_cast<Eigen::Index>(rows.size()), 4);
        for (std::size_t i = 0; i < rows.size(); ++i)
          content.table.row(i) << rows[i].drive_plus, rows[i].drive_minus, rows[i].meas_plus,
              rows[i].meas_minus;
      } else {
        const auto& pairs =
            reduced ? model.protocol().reduced_pairs() : model.protocol().pairs(order);
        content.table_name = "pairs";
        content.table.resize(static_cast<Eigen::Index>(pairs.size()), 2);
        for (std::size_t i = 0; i < pairs.size(); ++i)
          content.table.row(i) << pairs[i].drive, pairs[i].measure;
      }
      write_hdf5_matrix(args->out, content);
    }
    fmt::print("wrote the {} x {} Jacobian on {} to {}\n", J.rows(), J.cols(), args->basis,
               args->out);
  };
}

}  // namespace eitbench::cli
