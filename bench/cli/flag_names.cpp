#include "flag_names.h"

#include <map>
#include <vector>

namespace eitbench::cli {
namespace {

struct FieldFlag {
  const char* source;  // the options struct, or the enum a name is parsed into
  const char* field;
  const char* flag;
};
using Table = std::vector<FieldFlag>;

Table operator+(Table a, const Table& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// add_mesh_options (options.cpp). Without the coverage: reconstruct takes it from the data.
const Table kMesh = {{"DiskMeshOptions", "electrodes", "--electrodes"},
                     {"DiskMeshOptions", "radius", "--radius"},
                     {"MeshDensity", "name", "--density"}};
// add_shape_options (options.cpp).
const Table kShape = {{"ShapeMeshOptions", "electrodes", "--electrodes"},
                      {"ShapeMeshOptions", "width", "--width"},
                      {"ShapeMeshOptions", "height", "--height"},
                      {"ShapeMeshOptions", "electrode_coverage", "--electrode-coverage"},
                      {"ShapeMeshOptions", "electrode_positions", "--electrode-positions"},
                      {"SensorShape", "name", "--shape"}};
const Table kCoverage = {{"DiskMeshOptions", "electrode_coverage", "--electrode-coverage"}};
// add_model_options (options.cpp).
const Table kModel = {{"ForwardOptions", "current", "--current"},
                      {"ForwardOptions", "contact_impedance", "--contact-impedance"},
                      {"MeasurementOrder", "name", "--order"}};
const Table kOrder = {{"MeasurementOrder", "name", "--order"}};
// reconstruct: --lambda is every method's weight (TV's alpha), --tolerance TV's and GN's.
const Table kSolvers = {{"TikhonovOptions", "lambda", "--lambda"},
                        {"GreitOptions", "lambda", "--lambda"},
                        {"GaussNewtonOptions", "lambda", "--lambda"},
                        {"TotalVariationOptions", "alpha", "--lambda"},
                        {"TotalVariationOptions", "tolerance", "--tolerance"},
                        {"GaussNewtonOptions", "tolerance", "--tolerance"},
                        {"Prior", "name", "--method"},
                        {"Criterion", "name", "--choose"},
                        {"TotalVariationOptions", "choice", "--choose"},
                        {"GaussNewtonOptions", "choice", "--choose"},
                        {"GreitOptions", "choice", "--choose"},
                        {"Neighbours", "name", "--neighbours"}};
// The flags train and run share.
const Table kBudget = {{"BudgetRule", "max_doublings", "--doublings"},
                       {"BudgetRule", "tolerance", "--doubling-tolerance"},
                       {"TrainingOptions", "epochs", "--epochs"},
                       {"TrainingOptions", "learning_rate", "--lr"},
                       {"TrainingOptions", "patience", "--patience"},
                       {"TrainingOptions", "device", "--device"}};
const Table kTraining = {{"TrainingOptions", "steps", "--steps"},
                         {"TrainingOptions", "batch_size", "--batch"},
                         {"TrainingOptions", "validate_every", "--validate-every"},
                         {"TrainingOptions", "min_improvement", "--min-improvement"},
                         {"ScheduleOptions", "warmup_fraction", "--warmup"},
                         {"ScheduleOptions", "decay_fraction", "--decay"},
                         {"ScheduleOptions", "final_fraction", "--floor"},
                         {"NetworkOptions", "dropout", "--dropout"},
                         {"TrainingOptions", "resident", "--resident"},
                         {"TrainingOptions", "resident_max_gib", "--resident-max-gib"},
                         {"TrainingOptions", "precision", "--precision"},
                         {"TrainingOptions", "cuda_graphs", "--cuda-graphs"},
                         {"TrainingOptions", "channels_last", "--channels-last"}};

const std::map<std::string, Table>& tables() {
  static const std::map<std::string, Table> by_command = {
      {"mesh", kMesh + kCoverage + kShape},
      {"forward", kMesh + kCoverage + kShape + kModel},
      {"jacobian", kMesh + kCoverage + kModel + Table{{"PixelGrid", "size", "--pixels"}}},
      {"simulate",
       {{"DiskMeshOptions", "electrodes", "--electrodes"},
        {"MeshDensity", "name", "--density"},
        {"ForwardOptions", "contact_impedance", "--contact-impedance"}}},
      {"augment",
       kOrder + Table{{"SymmetrySearchOptions", "relative_tolerance", "--symmetry-tolerance"}}},
      {"import", kOrder},
      {"info", kOrder},
      {"reconstruct", kMesh + kOrder + kSolvers},
      {"calibrate", kMesh + Table{{"PressFrameOptions", "step_degrees", "--step"},
                                  {"PressFrameOptions", "touch_radius", "--touch-radius"},
                                  {"PressSensorOptions", "huber", "--huber"}}},
      {"train", kBudget + kTraining},
      {"run", kBudget + Table{{"KtcTankOptions", "electrode_coverage", "--electrode-coverage"},
                              {"MeshDensity", "name", "--density"},
                              {"KtcNoise", "relative", "--noise-relative"},
                              {"KtcNoise", "floor", "--noise-floor"},
                              {"KtcSetup", "grid", "--pixels"}}},
      {"ktc",
       {{"KtcTankOptions", "electrode_coverage", "--electrode-coverage"},
        {"MeshDensity", "name", "--density"},
        {"KtcNoise", "relative", "--noise-relative"},
        {"KtcNoise", "floor", "--noise-floor"},
        {"KtcSetup", "grid", "--pixels"},
        {"SegmentationKind", "name", "--segmentation"},
        {"SegmentationRule", "resistive", "--resistive"},
        {"SegmentationRule", "conductive", "--conductive"}}},
  };
  return by_command;
}

}  // namespace

InputError name_the_flag(const InputError& error, const std::string& command) {
  const auto table = tables().find(command);
  if (table == tables().end()) return error;
  for (const FieldFlag& row : table->second)
    if (error.source() == row.source && error.field() == row.field)
      return InputError(row.flag, "", error.message());
  return error;
}

}  // namespace eitbench::cli
