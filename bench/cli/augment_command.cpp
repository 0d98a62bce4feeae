// eitbench augment: frames moved by one group element, or expanded by a whole group.
#include <fmt/core.h>

#include <limits>

#include <memory>
#include <optional>

#include "commands.h"
#include "eitbench/augment.h"
#include "eitbench/bench/data/augment_file.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/csv.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/msh_io.h"
#include "options.h"

namespace eitbench::cli {

namespace {

// CSV frames of another protocol (its inputs, one frame a line), moved by signed channel
// permutations: --element, a group of D_L, or auto (the elements of D_L, or of the mesh's group,
// that map the protocol onto itself).
void augment_protocol_frames(const std::string& in, const std::string& out,
                             const MeasurementProtocol& protocol, const std::string& group,
                             const std::string& element, const std::string& mesh_path) {
  const int L = protocol.electrodes();
  const Eigen::MatrixXd frames = read_frames_csv(in, [&](std::size_t width, int line) {
    if (width != static_cast<std::size_t>(protocol.input_size()))
      throw InputError(in, "line " + std::to_string(line),
                       std::to_string(width) + " values; the " + protocol.name() +
                           " protocol has " + std::to_string(protocol.input_size()) + " inputs");
    return std::numeric_limits<std::size_t>::max();
  });
  std::vector<GroupElement> elements;
  if (!element.empty()) {
    elements = {parse_element(element, L, "--element")};
  } else if (group == "auto") {
    const auto candidates =
        mesh_path.empty()
            ? group_elements(AugmentGroup::dihedral, L)
            : find_sensor_group(read_msh_file(mesh_path), {}, mesh_path).frame_elements();
    elements = protocol_elements(protocol, candidates);
  } else {
    const AugmentGroup kind = parse_group(group, "--group");
    if (kind == AugmentGroup::paper)
      throw InputError(
          "--group", "",
          "paper is defined on the adjacent protocol's map, not on " + protocol.name());
    elements = group_elements(kind, L);
  }
  const auto moves = channel_actions(protocol, elements);  // refuses an element it breaks
  const Eigen::Index k = static_cast<Eigen::Index>(elements.size());
  Eigen::MatrixXd moved(frames.rows() * k, frames.cols());
  for (Eigen::Index i = 0; i < frames.rows(); ++i)
    for (Eigen::Index e = 0; e < k; ++e)
      moved.row(i * k + e) = moves[e].apply(frames.row(i).transpose()).transpose();
  write_frames_csv(out, moved);
  fmt::print("wrote {} frames ({} x {} element{}, {} protocol) to {}\n", moved.rows(),
             frames.rows(), k, k == 1 ? "" : "s", protocol.name(), out);
}

}  // namespace

std::function<void()> add_augment_command(CLI::App& app) {
  struct Args {
    std::string in, out, group, element, order = "rotating", split = "train", mesh;
    int electrodes = 16;
    SymmetrySearchOptions symmetry;
    ProtocolChoice protocol;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "augment",
      "Move frames by a symmetry of the sensor (--element) or expand them by a group (--group)");
  cmd->add_option("--in", args->in,
                  "an eitbench HDF5 data set, or CSV frames (one a line: L(L-3) values in --order, "
                  "or L(L-3)/2 reduced)")
      ->required();
  cmd->add_option("--out", args->out, "the same kind of file as --in")->required();
  cmd->add_option(
         "--split", args->split,
         "data sets: the split to augment (the others are copied): train | validation | test | all")
      ->capture_default_str()
      ->check(CLI::IsMember({"train", "validation", "test", "all"}));
  auto* group = cmd->add_option(
      "--group", args->group,
      "rotations | mirror | d16 | paper: each frame becomes |G| lines (rot:0..L-1, then "
      "mirror:0..L-1), identity first; auto (with --mesh, its default): the sensor's own group, "
      "found from the mesh, or for a data set the group of the sensor it was made on");
  auto* element = cmd->add_option(
      "--element", args->element,
      "rot:S (rotation by S electrode steps: the touch turns by -S) or mirror:S (the mirror "
      "through electrode 0, then rot:S)");
  group->excludes(element);
  cmd->add_option("--order", args->order, "order of full frames: rotating | ascending")
      ->capture_default_str()
      ->check(CLI::IsMember({"rotating", "ascending"}));
  auto* electrodes = cmd->add_option("--electrodes", args->electrodes, "electrodes L")
                         ->capture_default_str()
                         ->check(CLI::Range(4, 256));
  cmd->add_option("--mesh", args->mesh,
                  "CSV frames: the sensor's Gmsh mesh; its symmetry group is found and every "
                  "element used must be in it")
      ->excludes(electrodes);
  add_protocol_options(*cmd, args->protocol);
  cmd->add_option("--symmetry-tolerance", args->symmetry.relative_tolerance,
                  "with --mesh: points match within this fraction of the median boundary segment")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1.0));
  return [args, cmd] {
    if (!cmd->count("--group") && !cmd->count("--element")) {
      if (args->mesh.empty()) throw InputError("augment", "", "give --group or --element");
      args->group = "auto";
    }
    if (is_hdf5_file(args->in)) {
      if (!args->mesh.empty())
        throw InputError("--mesh", "",
                         "applies to CSV frames: a data set is augmented by the group of the "
                         "sensor it was simulated on");
      if (args->protocol.spec != "adjacent" || args->protocol.magnitude)  // a check asked for
        check_protocol_of(args->protocol, measurement_protocol(read_dataset(args->in)), args->in);
      FileAugmentOptions o;
      // auto: the group of the sensor the set was made on (D_L for the disk).
      o.group = cmd->count("--group") && args->group != "auto" ? parse_group(args->group, "--group")
                                                               : AugmentGroup::dihedral;
      if (cmd->count("--element"))
        o.elements = {parse_element(args->element, read_dataset(args->in).electrodes, "--element")};
      if (args->split == "all")
        o.splits = {Split::train, Split::validation, Split::test};
      else
        o.splits = {args->split == "train"        ? Split::train
                    : args->split == "validation" ? Split::validation
                                                  : Split::test};
      const long long n = augment_dataset_file(args->in, args->out, o);
      fmt::print("wrote {}: {} samples ({} split{} by {})\n", args->out, n, args->split,
                 args->split == "all" ? "s" : "",
                 cmd->count("--group") ? args->group : args->element);
      return;
    }
    if (const auto protocol = chosen_protocol(
            args->protocol,
            args->mesh.empty() ? args->electrodes : read_msh_file(args->mesh).num_electrodes());
        protocol && !is_adjacent(*protocol))
      return augment_protocol_frames(args->in, args->out, *protocol, args->group, args->element,
                                     args->mesh);
    if (args->group == "auto" && args->mesh.empty())
      throw InputError("--group", "", "auto needs --mesh: the group is found from the sensor");
    std::optional<Mesh> mesh;
    if (!args->mesh.empty()) mesh = read_msh_file(args->mesh);
    const int L = mesh ? mesh->num_electrodes() : args->electrodes;
    const MeasurementOrder order = parse_order(args->order);
    const Eigen::MatrixXd frames = read_frames_csv(args->in, [&](std::size_t width, int line) {
      try {  // a width no frame has refuses the file at its first line
        frame_layout(static_cast<Eigen::Index>(width), L, order, args->in);
      } catch (const InputError& e) {
        throw InputError(args->in, "line " + std::to_string(line), e.message());
      }
      return std::numeric_limits<std::size_t>::max();
    });
    const FrameLayout layout = frame_layout(frames.cols(), L, order, args->in);
    const bool by_group = !args->group.empty(), automatic = args->group == "auto";
    const AugmentGroup kind =
        by_group && !automatic ? parse_group(args->group, "--group") : AugmentGroup::dihedral;
    std::vector<GroupElement> elements =
        by_group ? (automatic ? std::vector<GroupElement>{} : group_elements(kind, L))
                 : std::vector<GroupElement>{parse_element(args->element, L, "--element")};
    if (mesh) {
      const SensorGroup group = find_sensor_group(*mesh, args->symmetry, args->mesh);
      if (automatic)
        elements = group.frame_elements();
      else if (kind == AugmentGroup::paper)
        throw InputError("--group", "",
                         "paper is the paper's column-reversal variant, not a symmetry of any "
                         "sensor: give auto or a group of the sensor");
      else
        require_sensor_symmetries(elements, *mesh, group, args->mesh);
      fmt::print("{}: symmetry group {} ({} element{})\n", args->mesh, group.name(), group.order(),
                 group.order() == 1 ? ": the frames are copied as they are" : "s");
    }
    const FrameSymmetry symmetry(L);
    const Eigen::Index k = static_cast<Eigen::Index>(elements.size());
    Eigen::MatrixXd out(frames.rows() * k, frames.cols());
    for (Eigen::Index i = 0; i < frames.rows(); ++i)
      for (Eigen::Index e = 0; e < k; ++e)
        out.row(i * k + e) =
            symmetry.apply(kind, elements[e], frames.row(i).transpose(), layout).transpose();
    write_frames_csv(args->out, out);
    fmt::print("wrote {} frames ({} x {}, {} layout) to {}\n", out.rows(), frames.rows(),
               by_group ? args->group : args->element, to_string(layout), args->out);
  };
}

}  // namespace eitbench::cli
