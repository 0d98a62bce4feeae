#pragma once
// The results store: the figures of a benchmark run and their files, results.json (everything, with
// the configuration, program and machine) and results.csv (tidy: one row per method x augmentation
// x SNR). One JSON form of each record serves results.json and the run's stage cache.
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eitbench/learned/trainer.h"

namespace eitbench {

// Touch metrics of one row (docs/benchmark.md#touch-metrics): where the touches are, how many and
// how large, against the data set's circles. Distances are fractions of the sensor radius R.
struct TouchCountScores {  // the frames with one true number of touches
  int touches = 0;         // true touches in each of them
  int frames = 0;
  double count_accuracy = NAN, centre_error_median = NAN;  // NaN median: nothing matched
};
// The true touches whose share of their frame's change lies in [from, to) (touch_signal.h), and
// how many of them a method found.
struct TouchSignalScores {
  double from = 0, to = INFINITY;
  int touches = 0, found = 0;
};

struct TouchScores {
  int frames = 0;  // frames scored; 0: not scored (no circles to compare with)
  // The blob threshold as a fraction of each image's in-disk maximum, chosen on validation frames;
  // NaN for a method that gives circles directly.
  double threshold = NAN;
  double count_accuracy = NAN;  // share of frames with the true number of touches
  // Over the matched touches (NaN when none matched): centre distance, and |r_found - r_true|.
  double centre_error_median = NAN, centre_error_p90 = NAN, radius_error_median = NAN;
  double missed_per_frame = NAN,
         phantom_per_frame = NAN;  // true touches unmatched, found unmatched
  int true_touches = 0, matched = 0;
  // The matched centre errors at 0, 5, ..., 100 % (21 values; empty when none matched): the
  // distribution the report's figure draws.
  std::vector<double> centre_error_quantiles;
  std::vector<TouchCountScores> by_count;  // ascending true count
  // Where the true touches' signals are known (else 0, NaN and empty): the frames whose every touch
  // is visible, the count accuracy on them, and the touches found by signal.
  int visible_frames = 0;
  double visible_count_accuracy = NAN;
  // The reconstruction model's misfit at the true circles, median over the noise-free test frames,
  // as a share of a frame: the error below which a touch is lost in the model's.
  double model_error_median = NAN;
  std::vector<TouchSignalScores> by_signal;  // ascending
};

struct ResultRow {
  std::string method;         // tikhonov | noser | laplace | smooth | tv | gn | greit | dnn
  std::string augment = "-";  // dnn: none | rotations | d16 | paper; "-" for model-based methods
  double snr_db = 0;          // infinity when noise-free ("inf" in the files)
  double cc = 0, re = 0, ssim = 0, mse = 0, cc_std = 0, re_std = 0;
  double latency_median_ms = 0, latency_p95_ms = 0, setup_s = 0;
  int frames = 0;        // frames scored (0: the data have no labels)
  std::string settings;  // hyperparameters and how they were chosen
  TouchScores touch;     // frames 0 when not scored (no circles; results.json of older runs)
  // Each test frame's CC and RE, in the data set's order (rounded to 1e-6; empty in runs from
  // before they were kept): compare pairs two runs' frames for its signed-rank test.
  std::vector<double> frame_cc, frame_re;
};

struct TrainingSummary {
  std::string augment;
  std::vector<TrainingRecord> history;  // one entry a validation
  int best_round = 0, best_epoch = 0;
  bool converged = false;  // the model ended the training; false: the budget did
  // How it ended (budget_rule.h: early stopping, floor, budget, rule, cap), the doublings taken,
  // the budget in steps at the end, and the best validation MSE after each stage (runs from
  // before the rule: early stopping or budget by `converged`, 0, 0, empty).
  std::string end;
  int doublings = 0;
  long long budget_steps = 0;
  std::vector<double> stage_best;
  long long steps = 0, samples = 0;  // optimiser steps and training samples seen
  double seconds = 0, samples_per_second = 0;
  // Training FLOP/s (3 forward passes a sample) over the machine's float32 GEMM peak.
  double fraction_of_gemm_peak = 0;
  // Inference on the training device when it is a GPU (empty device: not measured): one frame's
  // wall-clock median and batches of 1,000 frames, host memory in and out included.
  std::string inference_device;
  double device_latency_ms = 0, device_frames_per_second = 0;
};
nlohmann::json to_json(const TrainingSummary& summary);
TrainingSummary training_summary_from_json(const nlohmann::json& j, const std::string& source);

// One model of the data-efficiency sweep (the paper's Fig. 8): trained on the first train_size
// training frames, scored on the test split (noise-free).
struct EfficiencyPoint {
  std::string augment;  // none | d16
  // converged: early stopping, up to the main runs' step budget; equal_steps: d16 with exactly the
  // optimiser steps that no augmentation needed to converge at the same size (equal compute).
  std::string budget;
  int train_size = 0;
  long long steps = 0;
  int epochs = 0;  // epochs (passes over train_size samples) trained
  double test_mse = 0, cc = 0, re = 0;
  bool converged = false;
  long long samples_seen = 0;
  int best_epoch = 0;
  double training_samples_per_second = 0, fraction_of_gemm_peak = 0;
  double cc_std = 0, re_std = 0;  // over the test frames (0 in runs from before they were kept)
  int frames = 0;                 // test frames scored
};

// One method on real presses (run --measured SET --calibration CAL, docs/real-presses.md): where
// it puts each press of the scored set SET, against the press's known centre. Lengths in the
// mesh's unit (`unit`); the fraction divides the median by the sensor's radius.
struct MeasuredRow {
  std::string method;         // a model-based method, dnn, fingerprint or centre
  std::string augment = "-";  // dnn: the augmentation of its training (or fine-tuning)
  int finetune_n = 0;         // real labelled presses of CAL it was trained or fine-tuned on
  // simulation: tuned or trained on the simulated set only; calibration presses: tuned on CAL's
  // presses (model-based, fingerprint); fine-tuned: the simulated model fine-tuned on finetune_n
  // presses; real presses only: trained from scratch on them; none: predicting the centre.
  std::string training = "simulation";
  double centre_error_median = NAN, centre_error_mean = NAN, centre_error_p90 = NAN;
  double centre_error_fraction_of_radius = NAN;  // median / R
  std::string unit = "mesh unit";
  std::string calibration, scored;  // the sets' file names
  int frames = 0, none_found = 0;   // scored presses; those located at the centre for want of one
  // The same over the scored presses at positions no calibration press came within 0.01 R of
  // (novel_frames of them; 0 and NaN when there are none): generalisation, not recall.
  int novel_frames = 0;
  double novel_centre_error_median = NAN, novel_centre_error_mean = NAN;
  // The same over the scored presses within half the radius of the centre (inner_frames of them;
  // 0 and NaN when there are none): a press far from the electrodes changes every channel a
  // little, and on a real skin costs the one-step methods most (docs/real-presses.md).
  int inner_frames = 0;
  double inner_centre_error_mean = NAN;
  double latency_median_ms = NAN;  // NaN: not timed
  std::string settings;            // hyperparameters and how they were chosen
  // The same method's median centre error on the simulated test split (noise-free), x R: the
  // simulated-to-real drop is the real fraction against it. NaN where no simulated row exists.
  double simulated_fraction_of_radius = NAN;
  // A row that uses no label: its median centre error, x R, on the simulated test frames with one
  // touch drawn with the calibration set's measured noise and channel gains, tuned as the row is
  // (docs/real-presses.md#a-pick-without-labels). The report picks the lowest. NaN elsewhere.
  double like_sensor_fraction_of_radius = NAN;
  // A row without labels whose hyperparameter the real frames chose (GCV on CAL's frames), and
  // on every row without labels the real frames' misfit to the model over the references' noise
  // (NaN elsewhere): where the model's own error dwarfs the noise the simulation like the sensor
  // lacks it, and the pick keeps to the rows the real frames tuned (press_report.cpp).
  bool tuned_on_real_frames = false;
  double misfit_over_noise = NAN;
};
nlohmann::json to_json(const MeasuredRow& row);
MeasuredRow measured_row_from_json(const nlohmann::json& j);

struct RunResults {
  std::string program;
  std::map<std::string, std::string> configuration, machine;
  std::vector<ResultRow> rows;
  std::vector<TrainingSummary> training;
  std::vector<EfficiencyPoint> efficiency;
  std::vector<MeasuredRow> measured;  // real presses; empty without --measured
  std::string recommendation;
};

// One record as results.json holds it; the readers throw nlohmann::json's exceptions on a missing
// or mistyped field (parse_results_json turns them into InputError).
nlohmann::json to_json(const ResultRow& row);
ResultRow result_row_from_json(const nlohmann::json& j);
nlohmann::json to_json(const TouchScores& touch);             // null when touch.frames == 0
TouchScores touch_scores_from_json(const nlohmann::json& j);  // null: not scored
nlohmann::json to_json(const EfficiencyPoint& point);
EfficiencyPoint efficiency_point_from_json(const nlohmann::json& j);

void write_results_json(const std::string& path, const RunResults& results);
// InputError naming the file and the field on anything that is not a results.json.
RunResults read_results_json(const std::string& path);
RunResults parse_results_json(const std::string& text, const std::string& source);
RunResults parse_results_json(const nlohmann::json& doc, const std::string& source);
void write_results_csv(const std::string& path, const std::vector<ResultRow>& rows);
std::string snr_label(double snr_db);  // "inf" or "40"
// The (method, augment) pairs of `rows` in the order the run produced them, each once.
std::vector<std::pair<std::string, std::string>> methods_in_order(
    const std::vector<ResultRow>& rows);

}  // namespace eitbench
