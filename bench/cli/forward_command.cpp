// eitbench forward: one frame of measured voltages for a conductivity.
#include <fmt/core.h>

#include <memory>

#include "commands.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/csv.h"
#include "options.h"

namespace eitbench::cli {

std::function<void()> add_forward_command(CLI::App& app) {
  struct Args {
    MeshSource mesh;
    ConductivitySource sigma;
    ModelSetup model;
    ProtocolChoice protocol;
    std::string out;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "forward", "Simulate the measured voltages of a conductivity (complete electrode model)");
  add_mesh_options(*cmd, args->mesh);
  add_shape_options(*cmd, args->mesh);
  add_conductivity_options(*cmd, args->sigma);
  add_model_options(*cmd, args->model);
  add_protocol_options(*cmd, args->protocol);
  cmd->add_option("--out", args->out, "CSV file: the frame on one line")->required();
  return [args, cmd] {
    const Mesh mesh = load_mesh(args->mesh);
    apply_sensor(args->model, mesh);
    const Eigen::VectorXd sigma = load_conductivity(*cmd, args->sigma, mesh);
    const int L = mesh.num_electrodes();
    args->model.forward.protocol = chosen_protocol(args->protocol, L);
    const ForwardModel model(mesh, args->model.forward,
                             args->mesh.file.empty() ? "mesh" : args->mesh.file);
    if (const auto& p = args->model.forward.protocol) {  // any protocol: its channels or inputs
      if (args->model.values != "full" && args->model.values != "reduced")
        throw InputError("--values", "",
                         "with --protocol: full (every channel) or reduced (the inputs)");
      const ForwardSolution s = model.solve(sigma);
      const bool inputs = args->model.values == "reduced";
      const Eigen::VectorXd frame = inputs ? model.inputs(s) : model.measured(s);
      write_frames_csv(args->out, frame.transpose());
      fmt::print("wrote {} values ({} protocol{}{}) to {}; |v| max {:.6g}\n", frame.size(),
                 p->name(), inputs ? ", its inputs" : "", p->magnitude() ? ", magnitudes" : "",
                 args->out, frame.cwiseAbs().maxCoeff());
      return;
    }
    if (args->model.values == "map" || args->model.values == std::to_string(L * L)) {
      const Eigen::VectorXd map = model.adjacent_map(model.solve(sigma));
      write_frames_csv(args->out, map.transpose());
      fmt::print("wrote {} values (an L x L map, v(d, m) at d L + m) to {}; |v| max {:.6g}\n",
                 map.size(), args->out, map.cwiseAbs().maxCoeff());
      return;
    }
    const bool reduced = reduced_values(args->model, L);
    const MeasurementOrder order = parse_order(args->model.order);
    const Eigen::VectorXd full = model.frame(sigma, order);
    const Eigen::VectorXd frame = reduced ? model.protocol().reduce(full, order) : full;
    write_frames_csv(args->out, frame.transpose());
    fmt::print("wrote {} values ({} order{}) to {}; |v| max {:.6g}\n", frame.size(),
               args->model.order, reduced ? ", reciprocity-reduced" : "", args->out,
               frame.cwiseAbs().maxCoeff());
  };
}

}  // namespace eitbench::cli
