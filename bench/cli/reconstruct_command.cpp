// eitbench reconstruct: images from frames by one method, with scores when labels are known.
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>

#include "commands.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/measurements.h"
#include "eitbench/bench/data/noise.h"
#include "eitbench/bench/data/sensor.h"
#include "eitbench/bench/data/sensor_noise.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/methods/evaluate.h"
#include "eitbench/bench/methods/images_file.h"
#include "eitbench/bench/methods/metrics.h"
#include "eitbench/bench/methods/model_file.h"
#include "eitbench/bench/methods/press_placement.h"
#include "eitbench/bench/methods/press_scores.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/bench/methods/touch_metrics.h"
#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/support/timing.h"
#include "eitbench/bench/support/version.h"
#include "eitbench/jacobian.h"
#include "eitbench/solvers/missing_values.h"
#include "options.h"
#include "press_tuning.h"

namespace eitbench::cli {
namespace {

struct ReconstructArgs {
  std::string method = "noser", data, reference, frames, order = "rotating", variable, choose, out,
              model;
  MeshSource mesh;
  double background = 0, lambda = 0, snr = INFINITY;
  std::uint64_t noise_seed = 1;
  int pngs = 4;
  bool absolute = false;
  std::string neighbours = "pixels";
  double noser_exponent = 0.5;
  double smooth_length = 1.0;
  double tolerance = 0, robust = 0;
  std::string sensor;
  double discrepancy_factor = 1;
  std::string locate = "blob";
  std::string split = "test";
  int touches = 0;  // 0: every frame; else only those with this many true touches
  ProtocolChoice protocol;
  bool paired_reference = false, relative = false;
  std::vector<double> mark;      // --mark X,Y: a point to mark on the pictures
  double touch_threshold = 0.5;  // press sets: an image's touches, at this fraction of its maximum
  std::string calibration, calibration_frames;  // a press set that tunes the method
  std::string presses_csv;     // a press set: each press where it is and where the method put it
  bool placement_map = false;  // with --calibration: undo the bias measured on its presses
  bool noise_weights = false;  // weigh each value by one over its noise measured in --sensor
};

void add_reconstruct_options(CLI::App* cmd, ReconstructArgs* args) {
  cmd->add_option(
         "--method", args->method,
         "tikhonov | noser | laplace | smooth | tv | gn | greit | shape (circles fitted by the "
         "FEM) | shape-linear (by the Jacobian) | dnn (needs --model)")
      ->capture_default_str()
      ->check(CLI::IsMember(method_names()));
  cmd->add_option("--data", args->data,
                  "an eitbench data set (its test split), or frames in .csv/.npy/.npz/.mat")
      ->required();
  cmd->add_option("--reference", args->reference,
                  "reference frame for measured data (see 'import')");
  cmd->add_option("--variable", args->variable,
                  "array or variable holding the frames (.npz, .mat)");
  cmd->add_option("--split", args->split,
                  "the data set's split to reconstruct (validation: to tune a method by hand "
                  "without looking at the test frames)")
      ->capture_default_str()
      ->check(CLI::IsMember({"train", "validation", "test"}));
  cmd->add_option("--touches", args->touches,
                  "only the frames with this many true touches (a data set with circles), e.g. 1 "
                  "for the single-touch figures; before --frames")
      ->check(CLI::Range(1, 4));
  cmd->add_option("--frames", args->frames, "frames A:B of those selected (0-based, B excluded)");
  cmd->add_option("--order", args->order, "order of L(L-3)-value measured frames")
      ->capture_default_str()
      ->check(CLI::IsMember({"rotating", "ascending"}));
  add_protocol_options(*cmd, args->protocol);
  cmd->add_flag("--paired-reference", args->paired_reference,
                "measured frames: --reference holds one frame per frame, each frame minus its own");
  cmd->add_flag("--relative", args->relative,
                "measured frames: each change relative to its own reference, in the mean "
                "reference's units");
  add_mesh_options(*cmd, args->mesh);
  cmd->add_option("--background", args->background,
                  "conductivity the Jacobian is linearised at (default: the data set's, else 1)")
      ->check(kPositive);
  auto* lambda = cmd->add_option("--lambda", args->lambda,
                                 "regularisation weight (lambda; the TV weight alpha for tv; the "
                                 "BIC's penalty weight for shape)")
                     ->check(kPositive);
  auto* choose =
      cmd->add_option(
             "--choose", args->choose,
             "choose lambda: gcv | lcurve | discrepancy (one-step linear methods; gcv is their "
             "default; discrepancy: the residual at the measured noise of --sensor, from "
             "calibrate --noise) | validation (any method; needs a validation split). Without "
             "it and --lambda, tv, gn and greit keep their default weight")
          ->check(CLI::IsMember({"gcv", "lcurve", "discrepancy", "validation"}));
  lambda->excludes(choose);
  cmd->add_option("--neighbours", args->neighbours,
                  "laplace, tv: couple pixels (4-neighbour) or mesh elements (edge-sharing)")
      ->capture_default_str()
      ->check(CLI::IsMember({"pixels", "elements"}));
  cmd->add_option("--noser-exponent", args->noser_exponent,
                  "noser: p of its prior diag(A^T A)^p, in [0, 1] (0: the identity's images, 1: "
                  "the Levenberg-Marquardt scaling; pyEIT's Jacobian method defaults to 0.2)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--smooth-length", args->smooth_length,
                  "smooth: the distance at which its prior covariance falls to 1 %, in units of "
                  "the sensor's radius (KTC2023's baseline: 1)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--tolerance", args->tolerance,
                  "tv: relative change of x to stop at (default 1e-4); gn: relative decrease of "
                  "the objective (1e-4)")
      ->check(kPositive);
  cmd->add_option("--robust", args->robust,
                  "shape: Huber's loss on each measurement at this multiple of the start's "
                  "residual RMS (default: none)")
      ->check(kPositive);
  cmd->add_option("--discrepancy-factor", args->discrepancy_factor,
                  "--choose discrepancy: the residual's RMS is this multiple of the noise's "
                  "(Morozov's tau; above 1 allows for model error)")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1e6));
  cmd->add_option("--sensor", args->sensor,
                  "a calibrated sensor file (eitbench calibrate): the model's contact impedances, "
                  "current and background conductivity (unless --background); a file not fitted "
                  "to a reference (calibrate --noise or --presses alone) lends only its noise");
  cmd->add_option("--model", args->model, "dnn: the model file made by 'eitbench train'");
  cmd->add_flag("--absolute", args->absolute, "gn: fit the absolute frames, not the differences");
  cmd->add_option("--snr", args->snr,
                  "add white Gaussian noise at this SNR (dB) before reconstructing");
  cmd->add_option("--noise-seed", args->noise_seed, "seed of that noise")->capture_default_str();
  cmd->add_option("--touch-threshold", args->touch_threshold,
                  "a press set (import --touches): an image's touches are its blobs at or above "
                  "this fraction of its maximum; the strongest is where the method puts the press "
                  "(with --locate centroid, the centroid of every pixel at or above it)")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
  cmd->add_option("--locate", args->locate,
                  "a press set: where an image puts its press: blob (the centroid of its "
                  "strongest blob at --touch-threshold) | centroid (of every pixel at or above "
                  "it, pyEIT's rule)")
      ->capture_default_str()
      ->check(CLI::IsMember({"blob", "centroid"}));
  cmd->add_option("--calibration", args->calibration,
                  "a press set whose presses choose the method's hyperparameter by where it puts "
                  "them (the lowest mean centre error), never the scored presses");
  cmd->add_option("--calibration-frames", args->calibration_frames,
                  "frames A:B of --calibration (default all; in the scored file, frames that are "
                  "not scored)");
  cmd->add_flag("--placement-map", args->placement_map,
                "with --calibration: measure on its presses where the method puts a press against "
                "where it is (the true radius and the turn, by the radius it is put at) and undo "
                "that bias on the scored presses");
  cmd->add_flag("--noise-weights", args->noise_weights,
                "weigh each value in the data term by one over its own noise, as measured on the "
                "sensor's repeated references (--sensor FILE from calibrate --noise): values "
                "that wander between references count less (not greit: its own noise model makes "
                "the weights change nothing)");
  cmd->add_option("--presses-csv", args->presses_csv,
                  "a press set: write each press's frame, true x,y, the x,y where the method "
                  "put it (after --placement-map, if given) and the distance between (the data "
                  "set's unit) to this CSV file");
  cmd->add_option("--mark", args->mark,
                  "X,Y: mark this point on the pictures (a known touch, in the sensor's "
                  "coordinates)")
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--png", args->pngs, "PNG pictures of the first N frames beside --out")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  cmd->add_option("--out", args->out, "HDF5 file of images (and scores when labels are known)")
      ->required();
}

}  // namespace

namespace {

// The rows of `rows` whose frames have exactly `touches` true circles.
std::vector<int> with_touches(const Dataset& data, const std::vector<int>& rows, int touches,
                              const std::string& path) {
  if (data.circles.empty())
    throw InputError(path, "circles", "--touches needs a data set with its circles");
  std::vector<int> kept;
  for (int r : rows)
    if (static_cast<int>(data.circles[r].size()) == touches) kept.push_back(r);
  if (kept.empty())
    throw InputError(path, "circle_count",
                     "no frame of the split has " + std::to_string(touches) + " touches");
  return kept;
}

// The frames to reconstruct (the test split's, or all measured ones; --frames of those), their
// labels (N x 0 without) and the data set they came from.
struct Selection {
  Dataset data;
  std::vector<int> rows;
  SampleMatrix frames, labels;
};

Selection select_frames(const ReconstructArgs* args, const std::optional<Mesh>& mesh_file) {
  Selection s;
  Dataset& data = s.data;
  if (is_hdf5_file(args->data) && args->data.find(".mat") == std::string::npos) {
    data = read_dataset(args->data);
    check_protocol_of(args->protocol, measurement_protocol(data), args->data);
  } else {
    ImportOptions o;
    o.electrodes = mesh_file ? mesh_file->num_electrodes() : args->mesh.disk.electrodes;
    o.order = parse_order(args->order);
    o.variable = args->variable;
    o.protocol = chosen_protocol(args->protocol, o.electrodes);
    o.paired_reference = args->paired_reference;
    o.relative = args->relative;
    data = import_measurements(args->data, args->reference, o);
    if (const int same = frames_without_change(data))
      fmt::print(stderr, "warning: {} of {} frames equal the reference (no change anywhere)\n",
                 same, data.size());
  }
  std::vector<int>& selected = s.rows;
  const Split split = args->split == "train"        ? Split::train
                      : args->split == "validation" ? Split::validation
                                                    : Split::test;
  selected = data.indices(split);
  if (selected.empty())
    throw InputError(args->data, "split", "no " + args->split + " frames to reconstruct");
  if (args->touches > 0) selected = with_touches(data, selected, args->touches, args->data);
  const auto [a, b] = parse_range(args->frames, static_cast<int>(selected.size()));
  selected = std::vector<int>(selected.begin() + a, selected.begin() + b);
  SampleMatrix& frames = s.frames;
  SampleMatrix& labels = s.labels;
  frames.resize(static_cast<Eigen::Index>(selected.size()), data.differences.cols());
  labels.resize(static_cast<Eigen::Index>(selected.size()), data.labels.cols());
  if (args->absolute && args->method != "gn")
    throw InputError("--absolute", "", "only the gn method fits absolute frames");
  const MeasurementProtocol data_protocol = measurement_protocol(data);
  for (std::size_t k = 0; k < selected.size(); ++k) {
    frames.row(k) =
        args->absolute
            ? data_protocol.to_inputs(data.frames.row(selected[k]).transpose()).transpose()
            : Eigen::RowVectorXd(data.differences.row(selected[k]));
    if (data.has_labels()) labels.row(k) = data.labels.row(selected[k]);
  }
  if (std::isfinite(args->snr)) add_noise(frames, args->snr, args->noise_seed);
  check_frames(frames, args->data);
  return s;
}

// The mesh the model-based methods reconstruct on: the file's, the mesh a set on a sensor of
// another shape stores, or a disk for the data's sensor.
Mesh reconstruction_mesh(ReconstructArgs* args, const CLI::App& cmd, std::optional<Mesh> mesh_file,
                         const Dataset& data) {
  if (!mesh_file && has_sensor_mesh(data)) {
    if (cmd.count("--electrode-coverage"))
      throw InputError("--electrode-coverage", "",
                       args->data + " stores its sensor's mesh, whose electrodes are fixed");
    return stored_sensor_mesh(data);
  }
  if (args->mesh.file.empty() && !cmd.count("--electrodes"))
    args->mesh.disk.electrodes = data.electrodes;
  // The data's electrodes unless the user models them otherwise (a measured set's coverage is
  // only the import's default).
  if (!cmd.count("--electrode-coverage"))
    args->mesh.disk.electrode_coverage = data.electrode_coverage;
  Mesh mesh = mesh_file ? std::move(*mesh_file) : load_mesh(args->mesh);
  if (mesh.num_electrodes() != data.electrodes)
    throw InputError(args->mesh.file.empty() ? "--electrodes" : args->mesh.file, "electrodes",
                     "the mesh has " + std::to_string(mesh.num_electrodes()) +
                         " electrodes, the data " + std::to_string(data.electrodes));
  return mesh;
}

struct FrameSelection {
  SampleMatrix frames, labels;
};

// Frames and labels to choose a hyperparameter on: the validation split when the data have one,
// else the selected frames themselves.
FrameSelection tuning_frames(const ReconstructArgs* args, const Selection& s,
                             const std::string& choose) {
  const Dataset& data = s.data;
  const std::vector<int> val = data.indices(Split::validation);
  if (choose == "validation" && (val.empty() || !data.has_labels()))
    throw InputError(args->data, "split",
                     "--choose validation needs a data set with a labelled validation split");
  FrameSelection t{s.frames, s.labels};
  if (val.empty()) return t;
  t.frames.resize(static_cast<Eigen::Index>(val.size()), data.differences.cols());
  t.labels.resize(static_cast<Eigen::Index>(val.size()), data.labels.cols());
  for (std::size_t k = 0; k < val.size(); ++k) {
    t.frames.row(k) = data.differences.row(val[k]);
    if (data.has_labels()) t.labels.row(k) = data.labels.row(val[k]);
  }
  if (std::isfinite(args->snr)) add_noise(t.frames, args->snr, args->noise_seed + 1);
  return t;
}

// Each input's noise for --noise-weights (the sensor's noise.inputs), or empty without it. Their
// scale does not matter to a lambda chosen on the grid, which follows the weighted problem's
// trace; a fixed --lambda is on the weighted data's scale.
Eigen::VectorXd input_noise(const ReconstructArgs* args, const std::string& choose,
                            const std::optional<SensorFile>& sensor, int inputs) {
  if (!args->noise_weights) return {};
  // GREIT's matrix D Y^T (Y Y^T + lambda diag(Y Y^T))^-1 takes each value's noise as
  // proportional to its own signal: rows weighted by W give the same image from W y exactly.
  if (args->method == "greit")
    throw InputError("--noise-weights", "",
                     "changes nothing for greit (its noise model scales each value by its own "
                     "signal, so weighing the values gives the same image); use tikhonov, noser, "
                     "laplace, tv, gn, shape or shape-linear");
  // The discrepancy principle compares the residual with the noise's RMS in the frames' units;
  // weighed values are in units of their own noise.
  if (choose == "discrepancy")
    throw InputError("--noise-weights", "",
                     "is not combined with --choose discrepancy (which compares the unweighted "
                     "residual with the noise); use gcv or lcurve");
  if (!sensor || !sensor->noise || sensor->noise->inputs.size() == 0)
    throw InputError("--noise-weights", "",
                     "needs each value's measured noise: --sensor FILE with noise.inputs "
                     "(eitbench calibrate --noise SET.h5 --out FILE)");
  if (sensor->noise->inputs.size() != inputs)
    throw InputError(
        args->sensor, "noise.inputs",
        fmt::format("holds {} values; the frames have {}", sensor->noise->inputs.size(), inputs));
  return sensor->noise->inputs;
}

// The method on `problem`; with a noise per input, its data term weighed by it (MissingValues
// weighs and selects each frame's values before the method sees them).
std::unique_ptr<Reconstructor> make_method(const std::string& name,
                                           std::shared_ptr<const LinearProblem> problem,
                                           const MethodOptions& mo, const Eigen::VectorXd& noise) {
  if (noise.size() == 0) return make_reconstructor(name, problem, mo);
  return std::make_unique<MissingValues>(
      problem, name,
      [name, mo](std::shared_ptr<const LinearProblem> p) {
        return make_reconstructor(name, std::move(p), mo);
      },
      noise);
}

// A model-based method on the mesh (and the calibrated sensor, when given), its hyperparameter
// chosen as --choose says.
std::unique_ptr<Reconstructor> model_based(const ReconstructArgs* args, const CLI::App& cmd,
                                           const Selection& s, const Mesh& mesh,
                                           const std::optional<SensorFile>& sensor,
                                           const PixelGrid& grid, double background,
                                           std::optional<PlacementMap>* map) {
  ForwardOptions forward;
  forward.contact_impedance = s.data.contact_impedance;
  forward.current = s.data.current;
  forward.protocol = std::make_shared<const MeasurementProtocol>(measurement_protocol(s.data));
  if (sensor) apply_fitted_sensor(*sensor, forward);
  const auto model = std::make_shared<const ForwardModel>(
      mesh, forward, args->mesh.file.empty() ? "mesh" : args->mesh.file);
  const auto problem =
      std::make_shared<const LinearProblem>(make_linear_problem(model, background, grid));
  MethodOptions mo;
  mo.choose = cmd.count("--lambda")  ? "fixed"
              : args->choose.empty() ? find_method(args->method).default_choice
                                     : args->choose;
  mo.lambda = args->lambda;
  if (mo.choose == "discrepancy") {
    if (!sensor || !sensor->noise)
      throw InputError("--choose discrepancy", "",
                       "needs the sensor's measured noise: --sensor FILE with a noise object "
                       "(eitbench calibrate --noise SET.h5 --out FILE)");
    if (!(s.data.reference.cwiseAbs().maxCoeff() > 0))
      throw InputError(args->data, "reference",
                       "is zero: the discrepancy principle scales the measured noise by the "
                       "frames' reference (import --reference)");
    mo.noise = noise_in_units_of(*sensor->noise, s.data.reference);
    mo.discrepancy_factor = args->discrepancy_factor;
  }
  mo.absolute = args->absolute;
  mo.neighbours = args->neighbours;
  mo.noser_exponent = args->noser_exponent;
  mo.smooth_length = args->smooth_length;
  mo.tolerance = args->tolerance;
  mo.robust = args->robust;
  const Eigen::VectorXd noise = input_noise(args, mo.choose, sensor, problem->measurements());
  if (!args->calibration.empty()) {
    if (cmd.count("--lambda") || cmd.count("--choose"))
      throw InputError("--calibration", "", "chooses the hyperparameter: no --lambda or --choose");
    mo.choose = "validation";
    auto method = make_method(args->method, problem, mo, noise);
    const PressTuning t =
        press_tuning(args->calibration, args->calibration_frames, s.data, args->data, s.rows, grid,
                     args->touch_threshold, args->locate == "centroid");
    method->fit(t.frames, t.labels, t.score);
    if (args->placement_map) {
      const PressRule rule{args->locate == "centroid", args->touch_threshold};
      const auto found =
          located_presses(press_touches(method->reconstruct_all(t.frames), grid, rule));
      map->emplace(found, true_presses(t.truth), s.data.radius);
    }
    return method;
  }
  auto method = make_method(args->method, problem, mo, noise);
  if (mo.choose != "fixed") {
    const FrameSelection tuning = tuning_frames(args, s, mo.choose);
    method->fit(tuning.frames, tuning.labels,
                [&](const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
                  return correlation(x, y, grid);
                });
  }
  return method;
}

std::unique_ptr<Reconstructor> learned(const ReconstructArgs* args, const CLI::App& cmd,
                                       const Dataset& data) {
  if (args->model.empty())
    throw InputError("--model", "", "--method dnn needs a model file (eitbench train --out)");
  if (cmd.count("--lambda") || cmd.count("--choose"))
    throw InputError("--method dnn", "", "a trained model has no lambda to set or choose");
  LearnedModel model = read_model_file(args->model);
  check_model_fits(model, args->model, data.electrodes, image_grid(data));
  check_model_protocol(model, args->model, measurement_protocol(data));
  return make_learned_reconstructor(std::move(model));
}

// PNG pictures of the first --png frames beside --out: the image, and the label's centre row
// (or the frame itself without labels).
void write_pngs(const ReconstructArgs* args, const Selection& s, const Evaluation& result,
                const Mesh& mesh, const PixelGrid& grid) {
  const Dataset& data = s.data;
  const SampleMatrix& images = result.images;
  const std::string stem =
      (std::filesystem::path(args->out).parent_path() / std::filesystem::path(args->out).stem())
          .string();
  for (int k = 0; k < std::min<int>(args->pngs, static_cast<int>(images.rows())); ++k) {
    SampleFigure f;
    f.title = fmt::format("{} frame {}{}", args->method, s.rows[k],
                          data.has_labels() ? fmt::format(", CC {:.3f}", result.each[k].cc) : "");
    f.image = images.row(k).transpose();
    f.mask = grid.mask();
    f.image_min = std::min(0.0, f.image.minCoeff());
    f.image_max = std::max(1e-12, f.image.maxCoeff());
    f.outline = &mesh;
    f.radius = data.radius;
    if (args->mark.size() == 2) f.marks.emplace_back(args->mark[0], args->mark[1]);
    f.plot_title = data.has_labels() ? "label (truth), row through the centre" : "frame";
    f.x_label = data.has_labels() ? "pixel column" : "measurement";
    f.y_label = data.has_labels() ? "intensity" : "dv";
    if (data.has_labels()) {
      const int n = grid.size(), row = n / 2;
      std::vector<double> truth(n), recon(n);
      for (int j = 0; j < n; ++j)
        truth[j] = s.labels(k, row * n + j), recon[j] = images(k, row * n + j);
      f.series.resize(2);
      f.series[0].y = truth, f.series[0].label = "truth", f.series[0].colour = {40, 160, 40};
      f.series[1].y = recon, f.series[1].label = args->method;
    } else {
      const Eigen::VectorXd dv = s.frames.row(k).transpose();
      f.series.resize(1);
      f.series[0].y.assign(dv.data(), dv.data() + dv.size()), f.series[0].label = "dv";
    }
    draw_sample_png(f, fmt::format("{}_{}.png", stem, k));
  }
}

// A press set's frames scored by where the method puts each press, and the centre's floor.
struct PressResult {
  PressScores method, centre;
  std::vector<PressBand> bands;            // the method's, by the press's distance from the centre
  std::vector<Eigen::Vector2d> truth, at;  // each frame's press and where the method put it
};
std::optional<PressResult> press_result(const ReconstructArgs* args, const Selection& s,
                                        const Evaluation& result, const PixelGrid& grid,
                                        double background, const std::optional<PlacementMap>& map) {
  if (s.data.touches.empty()) return std::nullopt;
  std::vector<std::vector<PressTouch>> truth;
  for (int row : s.rows) truth.push_back(s.data.touches[static_cast<std::size_t>(row)]);
  const TouchFrames found =
      !result.circles.empty()
          ? touches_of(result.circles, background)
          : press_touches(result.images, grid, {args->locate == "centroid", args->touch_threshold});
  PressResult p{score_presses(found, truth), centre_floor(truth),
                score_presses_by_distance(found, truth, s.data.radius), true_presses(truth),
                located_presses(found)};
  if (map) {  // the positions moved by the map are what is scored
    p.at = map->apply(p.at);
    const int none = p.method.none_found;
    p.method = score_positions(p.at, truth);
    p.method.none_found = none;
    p.bands = score_positions_by_distance(p.at, truth, s.data.radius);
  }
  return p;
}

void write_presses_csv(const std::string& path, const std::vector<int>& rows,
                       const PressResult& p) {
  write_text_atomically(path, [&](std::ostream& out) {
    out << "frame,true_x,true_y,found_x,found_y,error\n";
    for (std::size_t i = 0; i < p.at.size(); ++i)
      out << fmt::format("{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", rows[i], p.truth[i].x(),
                         p.truth[i].y(), p.at[i].x(), p.at[i].y(), (p.at[i] - p.truth[i]).norm());
  });
}

void print_presses(const PressResult& p, double radius) {
  const auto line = [radius](const PressScores& s) {
    return fmt::format("median {:.4g}, mean {:.4g}, p90 {:.4g} ({:.3f} / {:.3f} / {:.3f} R)",
                       s.median, s.mean, s.p90, s.median / radius, s.mean / radius, s.p90 / radius);
  };
  fmt::print("  presses: centre error {}; {} of {} frames without a touch (placed at the centre)\n",
             line(p.method), p.method.none_found, p.method.frames);
  fmt::print("  predicting the centre: {}\n", line(p.centre));
  // Inner presses give weak, wide changes, and on a real skin most of a method's error.
  std::string bands;
  for (const PressBand& b : p.bands) {
    if (b.scores.frames == 0) continue;
    const std::string where = std::isfinite(b.outer) ? fmt::format("{:g}-{:g} R", b.inner, b.outer)
                                                     : fmt::format("from {:g} R", b.inner);
    bands += fmt::format("{}{} {:.3f} / {:.3f} ({})", bands.empty() ? "" : ", ", where,
                         b.scores.median / radius, b.scores.mean / radius, b.scores.frames);
  }
  fmt::print("  by the press's distance from the centre (median / mean, R; presses): {}\n", bands);
  // A bias, unlike scatter, is the model's: presses all put too far out, or turned one way.
  std::string placed;
  for (const PressBand& b : p.bands) {
    if (b.scores.frames == 0) continue;
    placed += fmt::format("{}{:.2f} R at {:.2f} R, turned {:+.0f} deg", placed.empty() ? "" : "; ",
                          b.placement.true_radius / radius, b.placement.found_radius / radius,
                          b.placement.turn_degrees);
  }
  fmt::print("  put where (each band's mean true radius at the mean found, median turn): {}\n",
             placed);
}

void write_images(const ReconstructArgs* args, const Selection& s, const Evaluation& result,
                  double background, double setup_s, const std::optional<PressResult>& presses) {
  ImagesFile file;
  file.images = result.images;
  file.frame_index = s.rows;
  file.scores = result.each;
  file.circles = result.circles;
  file.text = {{"method", args->method},
               {"settings", result.settings},
               {"data", args->data},
               {"program", program_version()},
               {"mesh", args->mesh.file.empty() ? "disk " + to_string(args->mesh.disk.density)
                                                : args->mesh.file}};
  file.numbers = {{"background", background},
                  {"setup_s", setup_s},
                  {"latency_median_ms", result.latency_median_ms},
                  {"latency_p95_ms", result.latency_p95_ms},
                  {"snr_db", args->snr}};
  if (presses) {  // in the mesh's unit
    file.numbers["press_centre_error_median"] = presses->method.median;
    file.numbers["press_centre_error_mean"] = presses->method.mean;
    file.numbers["press_centre_error_p90"] = presses->method.p90;
    file.numbers["press_frames_without_touch"] = presses->method.none_found;
    file.numbers["press_centre_floor_median"] = presses->centre.median;
    file.numbers["press_centre_floor_mean"] = presses->centre.mean;
  }
  write_images_file(args->out, file);
}

void print_summary(const ReconstructArgs* args, const Selection& s, const Evaluation& result,
                   double setup_s, const std::optional<PressResult>& presses) {
  fmt::print("{} ({}): {} frames, setup {:.3f} s, latency median {:.3f} ms, p95 {:.3f} ms\n",
             args->method, result.settings, result.images.rows(), setup_s, result.latency_median_ms,
             result.latency_p95_ms);
  const ScoreSummary& summary = result.scores;
  if (s.data.has_labels())
    fmt::print("  CC {:.4f} +- {:.4f}, RE {:.4f} +- {:.4f}, SSIM {:.4f}, MSE {:.3g}{}\n",
               summary.mean.cc, summary.std.cc, summary.mean.re, summary.std.re, summary.mean.ssim,
               summary.mean.mse,
               std::isfinite(args->snr) ? fmt::format(" at {} dB", args->snr) : "");
  if (!result.circles.empty() && !s.data.circles.empty()) {  // the shape fit: where, how many
    std::vector<std::vector<Circle>> truth;
    for (int row : s.rows) truth.push_back(s.data.circles[static_cast<std::size_t>(row)]);
    const TouchScores t = score_touches(touches_of(result.circles, s.data.background),
                                        touches_of(truth, s.data.background), s.data.radius);
    fmt::print(
        "  touches: count right in {:.0f} % of frames, centre error median {:.3f} R, p90 "
        "{:.3f} R; {:.2f} missed and {:.2f} phantom a frame\n",
        100 * t.count_accuracy, t.centre_error_median, t.centre_error_p90, t.missed_per_frame,
        t.phantom_per_frame);
  }
  if (presses) {
    print_presses(*presses, s.data.radius);
    if (result.circles.empty())
      fmt::print("  each press where its image puts it: the {} at {:g} x the image's maximum\n",
                 args->locate == "centroid" ? "centroid of every pixel" : "strongest blob",
                 args->touch_threshold);
  }
  if (s.data.has_labels() && !result.each.empty()) {  // a mean hides one runaway frame
    const auto worst = std::max_element(result.each.begin(), result.each.end(),
                                        [](const auto& a, const auto& b) { return a.re < b.re; });
    fmt::print("  worst RE {:.4f} (frame {})\n", worst->re, s.rows[worst - result.each.begin()]);
  }
  fmt::print("wrote {}\n", args->out);
}

}  // namespace

std::function<void()> add_reconstruct_command(CLI::App& app) {
  auto args = std::make_shared<ReconstructArgs>();
  auto* cmd = app.add_subcommand(
      "reconstruct", "Reconstruct images from frames (difference voltages) by one method");
  add_reconstruct_options(cmd, args.get());
  return [args, cmd] {
    // The mesh file, read once: its electrode count sets how measured frames are read.
    std::optional<Mesh> mesh_file;
    if (!args->mesh.file.empty()) mesh_file = read_msh_file(args->mesh.file);
    const Selection s = select_frames(args.get(), mesh_file);
    if (args->placement_map && args->calibration.empty())
      throw InputError("--placement-map", "",
                       "needs --calibration: the bias is measured on labelled presses");
    // The map is measured where the images put CAL's presses; the shape fits and the learned
    // model are scored otherwise (their circles; no calibration), so it would not apply to them.
    if (args->placement_map && !find_method(args->method).pixel_image)
      throw InputError("--placement-map", "",
                       "applies to methods whose images place the press (" +
                           joined_method_names_with(&MethodSpec::pixel_image) + "), not " +
                           args->method);
    if (!args->presses_csv.empty()) {
      if (s.data.touches.empty())
        throw InputError("--presses-csv", "",
                         args->data + " is not a press set (import --touches)");
      // Refused now, before any work or --out is written, if it may not be written (an input,
      // a folder that does not exist).
      temporary_path_for(args->presses_csv);
      if (std::filesystem::absolute(args->presses_csv).lexically_normal() ==
          std::filesystem::absolute(args->out).lexically_normal())
        throw InputError("--presses-csv", "", "is --out: the two are different files");
    }
    const Mesh mesh = reconstruction_mesh(args.get(), *cmd, std::move(mesh_file), s.data);
    const auto sensor = load_sensor(args->sensor, mesh.num_electrodes());
    const double background = cmd->count("--background")    ? args->background
                              : sensor && sensor->fitted    ? sensor->background
                              : s.data.preset == "imported" ? 1.0
                                                            : s.data.background;
    // The disk's grid, or the one covering the sensor mesh the set stores.
    const PixelGrid grid = image_grid(s.data);  // the labels' grid: a --mesh must fit it
    const auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<Reconstructor> method;
    std::optional<PlacementMap> map;  // --placement-map: measured on the calibration presses
    if (args->method == "dnn") {
      if (args->noise_weights)
        throw InputError("--noise-weights", "",
                         "weighs a model-based method's data term, not dnn's");
      method = learned(args.get(), *cmd, s.data);
    } else {
      if (!args->model.empty())
        throw InputError("--model", "", "only --method dnn takes a model file");
      method = model_based(args.get(), *cmd, s, mesh, sensor, grid, background, &map);
    }
    const double setup_s = seconds_since(t0);
    // The same loop as the benchmark's: every frame timed one at a time, after a warm-up.
    EvaluationOptions timing;
    timing.timed_frames = -1;
    timing.source = args->data;
    const Evaluation result =
        evaluate(*method, s.frames, s.data.has_labels() ? s.labels : SampleMatrix(), grid, timing);
    const auto presses = press_result(args.get(), s, result, grid, background, map);
    write_images(args.get(), s, result, background, setup_s, presses);
    if (presses && !args->presses_csv.empty())
      write_presses_csv(args->presses_csv, s.rows, *presses);
    write_pngs(args.get(), s, result, mesh, grid);
    if (map)
      fmt::print(
          "placement map: measured on {} calibration presses, kernel width {:.3g} R "
          "(leave-one-out centre error {:.3f} R); the scores below are after it\n",
          map->presses(), map->bandwidth() / s.data.radius,
          map->leave_one_out_error() / s.data.radius);
    print_summary(args.get(), s, result, setup_s, presses);
  };
}

}  // namespace eitbench::cli
