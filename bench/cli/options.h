#pragma once
// Options that several subcommands share: where the mesh and the conductivity come from, and how
// the forward model and its output are set up. Names are a contract (issue 2): scripts use them.
#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "eitbench/bench/data/simulate.h"
#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/jacobian.h"
#include "eitbench/jacobian/shape_mesh.h"

namespace eitbench::cli {

// "must be a positive number" / "... zero or more": CLI11's own PositiveNumber names its range up
// to the largest double, a 300-digit number.
extern const CLI::Validator kPositive;
extern const CLI::Validator kNonNegative;

struct MeshSource {
  std::string file;  // --mesh
  DiskMeshOptions disk;
  std::string density = "medium";
  // --shape and its sizes (add_shape_options): empty for the symmetric disk of `disk`.
  std::string shape;
  ShapeMeshOptions other;  // its electrode_positions: --electrode-positions f0,f1,...
};
void add_mesh_options(CLI::App& app, MeshSource& source);
// --shape, --width, --height, --electrode-positions: for commands that work on any sensor.
void add_shape_options(CLI::App& app, MeshSource& source);
Mesh load_mesh(MeshSource& source);  // a Gmsh file, a generated shape or a generated disk

struct ConductivitySource {
  double uniform = 0;       // --conductivity
  std::string file;         // --element-conductivity
  std::string circles;      // --circles
  double background = 1.0;  // --background
};
void add_conductivity_options(CLI::App& app, ConductivitySource& source);
Eigen::VectorXd load_conductivity(const CLI::App& app, const ConductivitySource& source,
                                  const Mesh& mesh);

struct ModelSetup {
  ForwardOptions forward;
  std::string sensor;  // --sensor: a calibrated sensor file
  std::string order = "rotating";
  std::string values = "full";  // 208 | 104 | full | reduced
};
void add_model_options(CLI::App& app, ModelSetup& setup);
// --sensor's contact impedances and current into setup.forward; InputError naming the file when
// it calibrates another electrode count than the mesh's.
void apply_sensor(ModelSetup& setup, const Mesh& mesh);
// The sensor file at `path` (none for an empty path), checked against the electrode count.
std::optional<SensorFile> load_sensor(const std::string& path, int electrodes);

// "A:B" -> frames [A, B) of n ("" for all; A or B may be left out); InputError(flag) otherwise.
std::pair<int, int> parse_range(const std::string& text, int n, const char* flag = "--frames");
// --protocol and --magnitude (docs/protocols.md).
struct ProtocolChoice {
  std::string spec = "adjacent";  // adjacent | adjacent-ascending | opposite | skip-K | FILE.csv
  bool magnitude = false;         // frames are |v|, as boards such as OpenEIT report
};
void add_protocol_options(CLI::App& app, ProtocolChoice& choice);
// --touch-radius MIN,MAX, --touch-contrast MIN,MAX, --randomise-electrodes DEG,
// --randomise-impedance S, --randomise-gain G,
// --randomise-snr MIN,MAX (docs/real-presses.md#simulating-the-fitted-sensor); checked by
// SimulationVariation::validate when the command runs.
void add_variation_options(CLI::App& app, SimulationVariation& variation);
// --shard K/N (docs/scaling.md): shard `index` of `count`; a parse error naming --shard otherwise.
void add_shard_option(CLI::App& app, int& index, int& count);
// The protocol for `electrodes` (InputError naming --protocol or the CSV file).
std::shared_ptr<const MeasurementProtocol> load_protocol(const ProtocolChoice& choice,
                                                         int electrodes);
// Null when the user chose neither flag (the adjacent protocol, or a data set's own), else
// load_protocol.
std::shared_ptr<const MeasurementProtocol> chosen_protocol(const ProtocolChoice& choice,
                                                           int electrodes);
// InputError(flag) when --protocol or --magnitude was given and the data set at `path` is read on
// another protocol: a set carries its protocol, which the flags may only confirm.
void check_protocol_of(const ProtocolChoice& choice, const MeasurementProtocol& data_protocol,
                       const std::string& path);
// True for the reciprocity-reduced L(L-3)/2 values; checks --values against L.
bool reduced_values(const ModelSetup& setup, int electrodes);

}  // namespace eitbench::cli
