// Stage 6: real presses (run --measured SET --calibration CAL). Every method of the run is scored
// on where it puts each press of SET. Each model-based method twice: tuned in simulation as the
// main rows are, and tuned on CAL's presses (the one-step methods a third time, by GCV on CAL's
// frames without their positions, and a fourth, GCV's lambda with the press rule on CAL; with CAL's
// references, the one-step methods and GREIT again in the simulation like the sensor,
// like_sensor.cpp); the learned models as trained in simulation; each of these again through its
// own position map fitted on CAL and through the sensor's press fit; floors from predicting the
// centre and from a fingerprint of CAL's labelled frames; and, with
// --finetune, the learned model fine-tuned on CAL's first n presses beside the same network trained
// on them alone. Nothing is tuned or trained on SET.
#include <fmt/core.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/measurements.h"
#include "eitbench/bench/data/training_data.h"
#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/bench/methods/model_file.h"
#include "eitbench/bench/methods/press_fingerprint.h"
#include "eitbench/bench/methods/press_labels.h"
#include "eitbench/bench/methods/press_scores.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/bench/methods/touches.h"
#include "eitbench/jacobian/error.h"
#include "stages.h"

namespace eitbench::run {
namespace fs = std::filesystem;
namespace {

// A press set brought to the model's units by its reference frame, as measured frames are in
// load_data: the same sensor, read on the simulated source's protocol.
struct PressFrames {
  std::string path, name;
  SampleMatrix frames;
  std::vector<std::vector<PressTouch>> touches;
  ReferenceCalibration scale;
  // The presses at a position no calibration press came within kNovel of: where the scores ask
  // whether a method generalises rather than recalls (recordings may repeat a press sequence).
  std::vector<bool> novel;
};

// x R: 0.7 mm on a 70 mm skin. A press this close to a calibration press is that spot pressed
// again; the others are new presses, though most lie among calibration presses (500 presses on
// the disk leave about 0.08 R between neighbours).
constexpr double kNovel = 0.01;

void mark_novel(PressFrames& set, const PressFrames& cal, double radius) {
  set.novel.assign(set.touches.size(), true);
  for (std::size_t i = 0; i < set.touches.size(); ++i)
    for (const auto& c : cal.touches)
      if (std::hypot(set.touches[i][0].x - c[0].x, set.touches[i][0].y - c[0].y) < kNovel * radius)
        set.novel[i] = false;
}

// Where a method put each press of the scored set, and how many it found nothing in (located
// at the centre).
struct Located {
  std::vector<Eigen::Vector2d> at;
  int none_found = 0;
  double latency_median_ms = NAN;  // one frame at a time, when the method was timed
  std::string settings;            // the method's, as evaluate reports them
};

Located located_in(const TouchFrames& found) {
  Located l;
  l.at = located_presses(found);
  for (const auto& f : found) l.none_found += f.empty();
  return l;
}

PressFrames press_frames(const std::string& path, const RunData& data) {
  const Dataset d = read_dataset(path);  // checked as a press set in load_data
  PressFrames p{path, fs::path(path).filename().string(), d.differences, d.touches, {}, {}};
  p.scale = calibrate_to_model(d.reference, data.source.reference);
  p.frames *= p.scale.scale;
  return p;
}

// What the stage's rows depend on besides the run's data: both sets and every option it reads.
Provenance measured_provenance(const RunConfig& config, const RunData& data) {
  Provenance p = training_provenance(config, data);
  p["scored presses"] = file_hash(config.measured);
  p["calibration presses"] = file_hash(config.press_calibration);
  std::string sizes;
  for (int n : config.finetune) sizes += std::to_string(n) + " ";
  p["finetune"] = sizes;
  p["finetune budget"] = fmt::format("{} steps, validation every {} samples", config.finetune_steps,
                                     config.finetune_validate_every);
  std::string methods;
  for (const auto& m : config.methods) methods += m + " ";
  p["methods"] = methods;
  p["scores"] = "all presses and those at new positions (0.01 R)";
  p["label-free rows"] = "one-step methods: GCV on CAL's frames, touch threshold 0.5";
  p["like the sensor"] =
      "200 + 200 one-touch simulated frames with CAL's reference noise and gains; lambda and "
      "rule there";
  p["press rule"] = "strongest blob or centroid, and the threshold, chosen on CAL";
  p["GCV rows with labels"] = "one-step methods: GCV on CAL's frames, the press rule on CAL";
  p["pick"] = "the rows the real frames tuned where their misfit passes twice the noise";
  p["sensor"] = file_hash(config.sensor);  // its press fit gives rows of its own
  p["calibrated rows"] = "sensor fit; each method's affine position map on CAL";
  p["press training"] = "fine-tuned at a tenth of the peak rate; from scratch at the peak rate";
  return p;
}

// Where `method` puts each press of `set`, with its latency and settings. A method that gives
// circles is located by them, the rest by their images and `rule`.
Located located_presses(const Reconstructor& method, const PixelGrid& grid, double background,
                        const PressFrames& set, const PressRule& rule, int timed_frames) {
  SampleMatrix images;
  std::vector<std::vector<Circle>> circles;
  const ResultRow r =
      evaluate_row(method, set.frames, SampleMatrix(), grid, timed_frames, &images, &circles);
  Located located = located_in(method.finds_circles() ? touches_of(circles, background)
                                                      : press_touches(images, grid, rule));
  located.latency_median_ms = r.latency_median_ms, located.settings = r.settings;
  return located;
}

// The press rule (strongest blob or centroid, and its threshold) with the lowest mean centre
// error on CAL's presses (choose_press_rule). With `on_cal`, also where the method puts CAL's
// presses by it (its position map's data), from the same reconstructions. A method that gives
// circles needs no rule (threshold NaN), and is located by them.
PressRule press_rule(const Reconstructor& method, const PixelGrid& grid, double background,
                     const PressFrames& cal, Located* on_cal = nullptr) {
  if (method.finds_circles()) {
    if (on_cal) *on_cal = located_presses(method, grid, background, cal, {}, 0);
    return {false, NAN};
  }
  const SampleMatrix images = method.reconstruct_all(cal.frames);
  const PressRule chosen = choose_press_rule(images, grid, cal.touches);
  if (on_cal) *on_cal = located_in(press_touches(images, grid, chosen));
  return chosen;
}

// "touch threshold 0.4 (on CAL)", and the centroid rule where it was chosen.
std::string rule_settings(const PressRule& rule, const char* how) {
  return fmt::format("touch threshold {:g}{} ({})", rule.threshold,
                     rule.centroid ? ", centroid of every pixel" : "", how);
}

struct StageInputs {
  const Context& context;
  const RunData& data;
  const Reconstruction& reconstruction;
  const PressFrames &set, &cal;
  const RunResults& simulated;
  // The sensor file's press fit (calibrate --presses on CAL), when it has one.
  const std::optional<SensorPressFit>& press_fit;
  const std::optional<LikeSensor>& like;  // the simulation like the sensor, when CAL allows it
};

// Positions on the model back in the recorded frame, by the inverse of the sensor's press fit.
Located through_fit(Located located, const SensorPressFit& fit) {
  for (Eigen::Vector2d& q : located.at)
    q = recorded_position(q, fit.rotate_degrees, fit.mirror, fit.scale);
  return located;
}

MeasuredRow row_for(const StageInputs& in, const std::string& method, const std::string& augment,
                    const std::string& training, const Located& located) {
  PressScores s = score_positions(located.at, in.set.touches);
  s.none_found = located.none_found;
  std::vector<Eigen::Vector2d> novel_at;
  std::vector<std::vector<PressTouch>> novel_truth;
  for (std::size_t i = 0; i < located.at.size(); ++i)
    if (in.set.novel[i])
      novel_at.push_back(located.at[i]), novel_truth.push_back(in.set.touches[i]);
  const PressScores novel = score_positions(novel_at, novel_truth);
  MeasuredRow row;
  row.novel_frames = novel.frames;
  row.novel_centre_error_median = novel.median, row.novel_centre_error_mean = novel.mean;
  const PressScores inner = score_positions_by_distance(located.at, in.set.touches,
                                                        in.reconstruction.grid.radius(), {0, 0.5})
                                .front()
                                .scores;
  row.inner_frames = inner.frames, row.inner_centre_error_mean = inner.mean;
  row.method = method, row.augment = augment, row.training = training;
  row.centre_error_median = s.median, row.centre_error_mean = s.mean, row.centre_error_p90 = s.p90;
  const double R = in.reconstruction.grid.radius();
  row.centre_error_fraction_of_radius = s.median / R;
  row.unit = "mesh unit";
  row.calibration = in.cal.name, row.scored = in.set.name;
  row.frames = s.frames, row.none_found = s.none_found;
  row.latency_median_ms = located.latency_median_ms, row.settings = located.settings;
  for (const ResultRow& r : in.simulated.rows)
    if (r.method == method && r.augment == augment && std::isinf(r.snr_db) && r.touch.frames > 0)
      row.simulated_fraction_of_radius = r.touch.centre_error_median;
  return row;
}

void log_row(const Context& context, const MeasuredRow& row) {
  context.say(fmt::format(
      "{:>12} {:>9} {:>19} n={:<4}: centre error median {:.3f} R, mean {:.3f} R, p90 {:.3f} R; "
      "new positions {:.3f} / {:.3f} R; within 0.5 R mean {:.3f} R{}{}",
      row.method, row.augment, row.training, row.finetune_n, row.centre_error_fraction_of_radius,
      row.centre_error_mean, row.centre_error_p90, row.novel_centre_error_median,
      row.novel_centre_error_mean, row.inner_centre_error_mean,
      row.none_found > 0 ? fmt::format(" ({} without a touch)", row.none_found) : "",
      std::isnan(row.like_sensor_fraction_of_radius)
          ? ""
          : fmt::format("; like the sensor in simulation {:.3f} R",
                        row.like_sensor_fraction_of_radius)));
}

// `row` again, scored at `moved` (its positions corrected by `how`, named in its training and
// settings).
MeasuredRow twin_of(const StageInputs& in, const MeasuredRow& row, const Located& moved,
                    const std::string& how, const std::string& settings) {
  MeasuredRow twin = row_for(in, row.method, row.augment, row.training + " + " + how, moved);
  twin.finetune_n = row.finetune_n;
  twin.settings = row.settings + "; " + settings;
  twin.simulated_fraction_of_radius = row.simulated_fraction_of_radius;
  log_row(in.context, twin);
  return twin;
}

// `row` again with its positions taken back to the recorded frame through the sensor's press fit.
MeasuredRow fitted_twin(const StageInputs& in, const MeasuredRow& row, const Located& located) {
  const SensorPressFit& fit = *in.press_fit;
  return twin_of(
      in, row, through_fit(located, fit), "sensor fit",
      fmt::format("positions / {:.4f}, turned by {:.2f} degrees{} (the sensor's press "
                  "fit on {})",
                  fit.scale, -fit.rotate_degrees, fit.mirror ? ", mirrored" : "", fit.presses));
}

// The affine map that best takes a method's positions of CAL's presses to their recorded centres
// (least squares over the presses it found a touch in): the systematic part of its error, such as
// EIT's pull towards the centre, learned from the calibration presses alone. None with fewer than
// 12 found presses (twice the map's six unknowns). A press found nowhere sits at the centre
// exactly (located_in), which a found blob's centroid never is.
std::optional<Eigen::Matrix<double, 3, 2>> position_map(const Located& on_cal,
                                                        const PressFrames& cal) {
  std::vector<Eigen::Index> found;
  for (std::size_t i = 0; i < on_cal.at.size(); ++i)
    if (on_cal.at[i] != Eigen::Vector2d::Zero()) found.push_back(static_cast<Eigen::Index>(i));
  if (found.size() < 12) return std::nullopt;
  Eigen::MatrixXd q(static_cast<Eigen::Index>(found.size()), 3), p(q.rows(), 2);
  for (Eigen::Index k = 0; k < q.rows(); ++k) {
    const auto i = static_cast<std::size_t>(found[static_cast<std::size_t>(k)]);
    q.row(k) << on_cal.at[i].x(), on_cal.at[i].y(), 1;
    p.row(k) << cal.touches[i][0].x, cal.touches[i][0].y;
  }
  return Eigen::Matrix<double, 3, 2>(q.colPivHouseholderQr().solve(p));
}

// `row` again with its positions moved by the method's own position map (position_map) fitted on
// CAL: presses it found nothing in stay at the centre.
std::optional<MeasuredRow> mapped_twin(const StageInputs& in, const MeasuredRow& row,
                                       const Located& located, const Located& on_cal) {
  const auto map = position_map(on_cal, in.cal);
  if (!map) return std::nullopt;
  Located moved = located;
  for (Eigen::Vector2d& q : moved.at)
    if (q != Eigen::Vector2d::Zero()) q = (Eigen::RowVector3d(q.x(), q.y(), 1) * *map).transpose();
  const auto& m = *map;
  return twin_of(in, row, moved, "position map",
                 fmt::format("positions through the affine map fitted on CAL's presses (x' = "
                             "{:.3f} x + {:.3f} y + {:.3f}, y' = {:.3f} x + {:.3f} y + {:.3f})",
                             m(0, 0), m(1, 0), m(2, 0), m(0, 1), m(1, 1), m(2, 1)));
}

// `row`'s twins: through the sensor's press fit when it has one, and through the method's own
// position map when `on_cal` (where it put CAL's presses) is given.
void push_twins(const StageInputs& in, const MeasuredRow& row, const Located& located,
                const Located* on_cal, std::vector<MeasuredRow>& rows) {
  if (in.press_fit) rows.push_back(fitted_twin(in, row, located));
  if (on_cal)
    if (auto twin = mapped_twin(in, row, located, *on_cal)) rows.push_back(*twin);
}

// The label-free tuning on real frames: GCV on CAL's frames, their positions unread.
constexpr const char* kOnFrames = "calibration frames (GCV)";
// Lambda as kOnFrames, the press rule and its threshold on CAL's presses: the labels tune the rule
// only. Lambda tuned on CAL's presses fits the spots CAL pressed; GCV's carries over to new ones
// (docs/real-presses.md#without-labelled-presses-held-out-by-time).
constexpr const char* kOnFramesRuleOnCal = "calibration frames (GCV), rule on CAL's presses";
// The label-free tuning in simulation: lambda and the press rule on the simulated validation
// frames drawn with CAL's measured noise and gains (like_sensor.cpp).
constexpr const char* kLikeSensor = "simulation like the sensor";

// A row without labels: its hyperparameter and press rule chosen as the row chose them, on the
// simulation like the sensor (GCV on its validation frames for a row tuned by GCV on CAL's, the
// validation CC and the rule on its labelled validation frames for a row tuned there), then its
// median centre error on that simulation's test frames: what the report picks by.
double like_sensor_score(const StageInputs& in, const std::string& name, bool by_gcv,
                         Reconstructor* tuned, const PressRule& rule) {
  if (!in.like) return NAN;
  const PixelGrid& grid = in.reconstruction.grid;
  if (!by_gcv) return like_sensor_median(*tuned, grid, *in.like, rule);
  MethodOptions mo;
  mo.choose = "gcv";
  auto method = make_reconstructor(name, in.reconstruction.problem, mo);
  method->fit(in.like->validation_frames, SampleMatrix(), nullptr);
  return like_sensor_median(*method, grid, *in.like, rule);
}

// A model-based method tuned two ways: in simulation (noise-free validation CC, as the main row
// at infinite SNR) and on CAL's presses (the lowest mean centre error); the one-step Tikhonov
// family a third way, by GCV on CAL's frames without their positions, the touch threshold fixed
// at 0.5: no label of any kind (docs/real-presses.md#lambda-without-labels); and, with the
// simulation like the sensor, each method that does not sweep on a subset a fourth way, lambda
// and the press rule chosen there (docs/real-presses.md#a-pick-without-labels); the one-step
// methods a fifth way, lambda by GCV and the press rule on CAL's presses.
void model_based_rows(const StageInputs& in, const std::string& name,
                      std::vector<MeasuredRow>& rows) {
  const RunConfig& config = in.context.config;
  const MethodSpec& spec = find_method(name);
  const PixelGrid& grid = in.reconstruction.grid;
  const double background = in.reconstruction.problem->background;
  for (const std::string training :
       {"simulation", kOnFrames, kLikeSensor, "calibration presses", kOnFramesRuleOnCal}) {
    const bool gcv_rule_on_cal = training == kOnFramesRuleOnCal;
    const bool on_frames = training == kOnFrames || gcv_rule_on_cal, like = training == kLikeSensor;
    if (on_frames && spec.default_choice != "gcv") continue;  // GCV is the one-step methods'
    // The iterative methods and the shape fit would sweep on few frames: left to the others.
    if (like && (!in.like || spec.sweep_on_subset)) continue;
    Eigen::Index tuned_on = 0;  // real presses
    MethodOptions mo;
    mo.choose = on_frames ? "gcv" : "validation";
    auto method = make_reconstructor(name, in.reconstruction.problem, mo);
    if (like && method->finds_circles()) continue;
    PressRule like_rule;  // the row's press rule in the simulation like the sensor
    if (on_frames) {
      method->fit(in.cal.frames, SampleMatrix(), nullptr);
    } else if (like) {
      fit_on_validation(*method, name, config, in.like->validation_frames,
                        in.like->validation_labels, grid);
      like_rule = choose_press_rule(method->reconstruct_all(in.like->validation_frames), grid,
                                    in.like->validation_touches);
    } else if (training == std::string("simulation")) {
      fit_on_validation(*method, name, config, in.data.validation.frames, in.data.validation.labels,
                        grid);
    } else {
      // The iterative methods sweep on CAL's first presses: a solve per frame and candidate.
      const Eigen::Index n = spec.sweep_on_subset ? std::min<Eigen::Index>(8 * config.sweep_frames,
                                                                           in.cal.frames.rows())
                                                  : in.cal.frames.rows();
      const std::vector<std::vector<PressTouch>> touches(in.cal.touches.begin(),
                                                         in.cal.touches.begin() + n);
      method->fit(in.cal.frames.topRows(n), press_labels(touches, grid, in.cal.path),
                  press_score(grid, 0.5));
      tuned_on = n;
    }
    // The map is CAL's: a method tuned without labels keeps to labels it never saw.
    const bool mapped = training == std::string("calibration presses");
    Located on_cal;
    const bool label_free = (on_frames && !gcv_rule_on_cal) || like;
    const PressRule rule =
        label_free ? like_rule
                   : press_rule(*method, grid, background, in.cal, mapped ? &on_cal : nullptr);
    const Located located =
        located_presses(*method, grid, background, in.set, rule, config.timed_frames);
    MeasuredRow row = row_for(in, name, "-", training, located);
    row.finetune_n = static_cast<int>(tuned_on);
    if (label_free) {
      row.like_sensor_fraction_of_radius =
          like_sensor_score(in, name, on_frames, method.get(), rule) / grid.radius();
      row.tuned_on_real_frames = on_frames;
      if (in.like) row.misfit_over_noise = in.like->misfit / in.like->noise.noise;
    }
    if (!std::isnan(rule.threshold))
      row.settings += ", " + rule_settings(rule, label_free && on_frames ? "fixed: no labels"
                                                 : like ? "on the simulation like the sensor"
                                                        : "on CAL");
    if (like)
      row.settings += fmt::format(
          "; simulated with CAL's noise ({:.3g} % of the reference) and "
          "gains (spread {:.2f})",
          100 * in.like->noise.noise, in.like->noise.gain_spread);
    log_row(in.context, row);
    rows.push_back(row);
    push_twins(in, row, located, mapped ? &on_cal : nullptr, rows);
  }
}

// A learned model scored as it is; its threshold chosen on CAL's presses, or 0.5 when it may not
// see them (a model fine-tuned on a few must not be tuned on the rest). With `twins`, its twins
// (push_twins) go there.
MeasuredRow learned_row(const StageInputs& in, const LearnedModel& model,
                        const std::string& augment, const std::string& training, int n,
                        bool threshold_on_cal, std::vector<MeasuredRow>* twins = nullptr) {
  const auto method = make_learned_reconstructor(model);
  const PixelGrid& grid = in.reconstruction.grid;
  Located on_cal;
  const PressRule rule = threshold_on_cal
                             ? press_rule(*method, grid, 0, in.cal, twins ? &on_cal : nullptr)
                             : PressRule{};
  const Located located =
      located_presses(*method, grid, 0, in.set, rule, in.context.config.timed_frames);
  MeasuredRow row = row_for(in, "dnn", augment, training, located);
  row.finetune_n = n;
  row.settings =
      rule_settings(rule, threshold_on_cal ? "on CAL" : "fixed: no presses to tune it on");
  if (training != "simulation") row.simulated_fraction_of_radius = NAN;
  log_row(in.context, row);
  if (twins) push_twins(in, row, located, &on_cal, *twins);
  return row;
}

// The learned model trained in simulation, its press rule chosen on the simulation like the
// sensor instead of on CAL's presses: a row without labels. No candidate for the pick: the
// simulation's one-touch frames were among its training samples.
MeasuredRow learned_like_row(const StageInputs& in, const LearnedModel& model,
                             const std::string& augment) {
  const auto method = make_learned_reconstructor(model);
  const PixelGrid& grid = in.reconstruction.grid;
  const PressRule rule = choose_press_rule(method->reconstruct_all(in.like->validation_frames),
                                           grid, in.like->validation_touches);
  const Located located =
      located_presses(*method, grid, 0, in.set, rule, in.context.config.timed_frames);
  MeasuredRow row = row_for(in, "dnn", augment, "simulation, rule like the sensor", located);
  row.settings = rule_settings(rule, "on the simulation like the sensor");
  log_row(in.context, row);
  return row;
}

// A model trained on presses, and how its training ended (for the row's settings).
struct PressModel {
  LearnedModel model;
  std::string training;
};

// The network trained on CAL's first n presses (every fifth held out for early stopping), from
// `start`'s weights or, without it, from scratch.
PressModel trained_on_presses(const StageInputs& in, const LearnedSetup& setup, int n,
                              AugmentGroup group, const LearnedModel* start) {
  const RunConfig& config = in.context.config;
  const PixelGrid& grid = in.reconstruction.grid;
  std::vector<int> train_rows, validation_rows;
  for (int i = 0; i < n; ++i) (i % 5 == 4 ? validation_rows : train_rows).push_back(i);
  auto take = [&](const std::vector<int>& rows) {
    LabelledFrames f;
    f.frames.resize(static_cast<Eigen::Index>(rows.size()), in.cal.frames.cols());
    std::vector<std::vector<PressTouch>> touches;
    for (std::size_t k = 0; k < rows.size(); ++k) {
      f.frames.row(static_cast<Eigen::Index>(k)) = in.cal.frames.row(rows[k]);
      touches.push_back(in.cal.touches[static_cast<std::size_t>(rows[k])]);
    }
    f.labels = press_labels(touches, grid, in.cal.path);
    return f;
  };
  TrainingOptions o = setup.training;
  o.augment = group;
  o.epochs = 0;
  o.steps = config.finetune_steps;
  o.validate_every = config.finetune_validate_every;
  o.batch_size = std::min(o.batch_size, std::max(2, static_cast<int>(train_rows.size())));
  // Its own schedule, as its own steps: --decay (the quick preset's 0.9) is the simulated
  // training's, measured there; the fine-tuning keeps the schedule it was measured with.
  o.schedule.decay_fraction = ScheduleOptions().decay_fraction;
  // A fine-tuning starts near its optimum: a tenth of the training's peak rate. From scratch the
  // network first sits on blank images (the nearest optimum of the MSE against small discs): the
  // validations lie far enough apart (config.finetune_validate_every) that early stopping does
  // not end a training on that plateau.
  if (start) o.learning_rate /= 10;
  Trainer trainer(setup.network, o, take(train_rows), take(validation_rows),
                  sensor_of(in.data.source));
  if (start) trainer.start_from(*start, "dnn (trained in simulation)");
  while (!trainer.done()) trainer.run_round();
  const auto& history = trainer.history();
  const TrainingRecord& best = history[static_cast<std::size_t>(trainer.best_round() - 1)];
  return {trainer.best_model(),
          fmt::format("{} train / {} validation presses, lr {:g}, best of {} steps at step {} "
                      "(validation MSE {:.4g}){}",
                      train_rows.size(), validation_rows.size(), o.learning_rate,
                      history.back().steps, best.steps, best.validation_loss,
                      trainer.converged() ? ", converged (early stopping)"
                                          : ", not converged: the step budget ran out")};
}

void finetune_rows(const StageInputs& in, const LearnedSetup& setup, const LearnedModel& base,
                   std::vector<MeasuredRow>& rows) {
  const int available = static_cast<int>(in.cal.frames.rows());
  for (int asked : in.context.config.finetune) {
    const int n = asked < 0 ? available : std::min(asked, available);
    if (asked > available)
      in.context.say(
          fmt::format("finetune: {} presses asked, CAL has {}: all of them", asked, available));
    if (n == 0) continue;  // the model as trained in simulation: its own row above
    for (const std::string augment : {"none", "d16"})
      for (const bool scratch : {false, true}) {
        in.context.say(fmt::format("dnn {} {} on {} real presses", augment,
                                   scratch ? "trained from scratch" : "fine-tuned", n));
        const PressModel m = trained_on_presses(in, setup, n, parse_group(augment, "augment"),
                                                scratch ? nullptr : &base);
        rows.push_back(learned_row(in, m.model, augment,
                                   scratch ? "real presses only" : "fine-tuned", n, false));
        rows.back().settings += "; " + m.training;
      }
  }
}

std::vector<MeasuredRow> measured_rows(const StageInputs& in, const LearnedSetup& setup,
                                       const std::vector<std::string>& augments) {
  const RunConfig& config = in.context.config;
  std::vector<MeasuredRow> rows;
  MeasuredRow centre =
      row_for(in, "centre", "-", "none",
              Located{std::vector<Eigen::Vector2d>(in.set.touches.size(), Eigen::Vector2d::Zero()),
                      0, NAN, ""});
  log_row(in.context, centre);
  rows.push_back(centre);

  Eigen::MatrixX2d positions(in.cal.frames.rows(), 2);
  for (Eigen::Index i = 0; i < positions.rows(); ++i)
    positions.row(i) << in.cal.touches[i][0].x, in.cal.touches[i][0].y;
  const PressFingerprint fingerprint(in.cal.frames, positions);
  std::vector<Eigen::Vector2d> at;
  for (Eigen::Index i = 0; i < in.set.frames.rows(); ++i)
    at.push_back(fingerprint.locate(in.set.frames.row(i).transpose()));
  MeasuredRow nearest =
      row_for(in, "fingerprint", "-", "calibration presses", Located{at, 0, NAN, ""});
  nearest.finetune_n = static_cast<int>(in.cal.frames.rows());
  nearest.settings = fmt::format("{} nearest frames (leave-one-out on CAL: {:.3f})",
                                 fingerprint.neighbours(), fingerprint.leave_one_out_error());
  log_row(in.context, nearest);
  rows.push_back(nearest);

  for (const std::string& name : config.methods) model_based_rows(in, name, rows);
  const LearnedModel* base = nullptr;
  std::vector<LearnedModel> models;
  models.reserve(augments.size());
  for (const std::string& augment : augments) {
    models.push_back(read_model_file(learned_model_path(in.context, augment)));
    std::vector<MeasuredRow> twins;
    rows.push_back(learned_row(in, models.back(), augment, "simulation", 0, true, &twins));
    rows.insert(rows.end(), twins.begin(), twins.end());
    if (in.like) rows.push_back(learned_like_row(in, models.back(), augment));
    // Fine-tuning starts from the model trained with the whole group when there is one.
    if (!base || augment == "d16") base = &models.back();
  }
  if (base && !config.finetune.empty()) finetune_rows(in, setup, *base, rows);
  return rows;
}

}  // namespace

// Refused when fitted on the scored presses: nothing may be tuned on them.
std::optional<SensorPressFit> sensor_press_fit(const RunConfig& config) {
  if (config.sensor.empty()) return std::nullopt;
  std::optional<SensorPressFit> fit = read_sensor_file(config.sensor).press_fit;
  if (!fit) return fit;
  // The same bytes wherever the file lies (a copy, another folder); by name for a file written
  // by hand without the hash.
  const bool same = fit->presses_hash.empty()
                        ? fs::path(fit->presses).filename() == fs::path(config.measured).filename()
                        : fit->presses_hash == file_hash(config.measured);
  if (same)
    throw InputError(config.sensor, "press_fit.presses",
                     "was fitted on " + fit->presses +
                         ", the presses --measured scores: fit it on the calibration presses "
                         "(calibrate --presses CAL --out)");
  return fit;
}

std::vector<MeasuredRow> run_measured(const Context& context, const RunData& data,
                                      const Reconstruction& reconstruction,
                                      const LearnedSetup& setup,
                                      const std::vector<std::string>& augments,
                                      const RunResults& simulated) {
  const RunConfig& config = context.config;
  const Provenance provenance = measured_provenance(config, data);
  std::vector<MeasuredRow> rows;
  if (context.cache.find("measured", provenance, [&](const nlohmann::json& j) {
        for (const auto& r : j) rows.push_back(measured_row_from_json(r));
      })) {
    context.say("real presses: resumed");
    return rows;
  }
  PressFrames set = press_frames(config.measured, data);
  const PressFrames cal = press_frames(config.press_calibration, data);
  mark_novel(set, cal, reconstruction.grid.radius());
  context.say(fmt::format(
      "real presses: scoring on {} ({} presses), tuning on {} ({} presses); frames x {:.6g} and "
      "x {:.6g} by their reference frames (cosine {:.4f}, {:.4f} with the model's)",
      set.name, set.frames.rows(), cal.name, cal.frames.rows(), set.scale.scale, cal.scale.scale,
      set.scale.fit, cal.scale.fit));
  context.say(fmt::format(
      "real presses: {} of the {} scored presses lie farther than {:g} R from every calibration "
      "press (scored apart as new positions)",
      std::count(set.novel.begin(), set.novel.end(), true), set.novel.size(), kNovel));
  const std::optional<SensorPressFit> press_fit = sensor_press_fit(config);
  if (press_fit)
    context.say(fmt::format(
        "real presses: the sensor's press fit (on {}): recorded positions x {:.4f}, turned by "
        "{:.2f} degrees{}; the methods that locate presses on the model get a second row through "
        "it",
        press_fit->presses, press_fit->scale, press_fit->rotate_degrees,
        press_fit->mirror ? " after the mirror" : ""));
  const std::optional<LikeSensor> like =
      like_sensor(context, data, reconstruction.problem, cal.frames);
  const StageInputs in{context, data, reconstruction, set, cal, simulated, press_fit, like};
  rows = measured_rows(in, setup, augments);
  nlohmann::json j = nlohmann::json::array();
  for (const MeasuredRow& r : rows) j.push_back(to_json(r));
  context.cache.save("measured", provenance, j);
  return rows;
}

}  // namespace eitbench::run
