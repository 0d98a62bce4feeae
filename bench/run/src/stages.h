#pragma once
// Internal: the benchmark run's stages. Each takes what it needs as typed input and returns what
// the next ones use; benchmark_run.cpp calls them in order:
//
//   load_data -> set_up_reconstruction -> noisy_copies -> run_model_based (each method)
//             -> run_learned (each augmentation) -> run_sweep -> the results store -> the report
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "eitbench/bench/data/dataset.h"
#include "eitbench/bench/data/measurements.h"
#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/bench/methods/press_scores.h"
#include "eitbench/bench/methods/touch_signal.h"
#include "eitbench/bench/report/results.h"
#include "eitbench/bench/run/config.h"
#include "eitbench/learned.h"
#include "eitbench/solvers.h"
#include "stage_cache.h"

namespace eitbench::run {

// What every stage shares: the configuration, the output folder, the stage cache, the log.
struct Context {
  const RunConfig& config;
  std::filesystem::path out;
  StageCache cache;
  void say(const std::string& line) const;
};

// Frames (difference, reduced layout), their labels (N x 0 without labels) and their circles (the
// touches' truth; empty without).
struct FrameSet {
  SampleMatrix frames, labels;
  std::vector<std::vector<Circle>> circles;
};

// 1. The data: `data` is evaluated; `source` trains the learned model and tunes hyperparameters.
// They are the same set when the data have labelled train and validation splits; otherwise the
// simulated preset is the source and the evaluated frames are calibrated to its units.
struct RunData {
  Dataset data, source;
  bool own_training = true;          // source is data
  bool labelled = true;              // the test frames have labels
  FrameSet test;                     // data's test split (all frames of unlabelled measurements)
  FrameSet validation;               // source's validation split
  ReferenceCalibration calibration;  // of the test frames, when !own_training
  std::vector<double> snrs;          // the SNRs evaluated (the data's own for measured frames)
  std::string data_path;             // where the evaluated data came from
  Provenance provenance;             // what every stage's results depend on (provenance.h)
  // The sensor the methods are set up for: that of the data that tune and train them.
  const Dataset& sensor() const { return own_training ? data : source; }
};
RunData load_data(const Context& context);
std::string describe(const ReferenceCalibration& calibration);

// 2. The reconstruction model for the source's sensor: mesh, Jacobian and pixel map.
struct Reconstruction {
  Mesh mesh;
  PixelGrid grid;
  std::shared_ptr<const LinearProblem> problem;  // shared with every method built on it
  double setup_s = 0;                            // time to build it
  // The test frames' true touches' shares of their change on this model, and its misfit at them
  // (touch_signal.h); empty when the test frames have no circles.
  TouchVisibility test_touches;
};
Reconstruction set_up_reconstruction(const Context& context, const RunData& data);

// Noisy copies of the test and validation frames, one seed per SNR.
struct NoisyFrames {
  std::vector<SampleMatrix> test, validation;  // by SNR
};
NoisyFrames noisy_copies(const RunConfig& config, const RunData& data);

// A method's rows (one per SNR) and the noise-free images of the first test frames.
struct MethodResults {
  std::vector<ResultRow> rows;
  std::vector<Eigen::VectorXd> images;
};

// A model-based method's hyperparameter by mean CC on validation frames (the iterative methods'
// on the first config.sweep_frames): how the run tunes every method in simulation.
void fit_on_validation(Reconstructor& method, const std::string& name, const RunConfig& config,
                       const SampleMatrix& frames, const SampleMatrix& labels,
                       const PixelGrid& grid);

// 3. A model-based method: its hyperparameter by validation CC at each SNR, scored on the test set.
MethodResults run_model_based(const Context& context, const std::string& method,
                              const RunData& data, const Reconstruction& reconstruction,
                              const NoisyFrames& noisy);

// 4. The learned reconstructor with one augmentation: trained (or read back), scored at each SNR.
struct LearnedResults {
  MethodResults method;
  TrainingSummary training;
  long long parameters = 0;
};
// The network and training options every learned model of the run shares.
struct LearnedSetup {
  NetworkOptions network;
  TrainingOptions training;
  double gemm_flops = 0;  // float32 matrix-product FLOP/s of this machine (CPU; 0: not measured)
};
LearnedSetup learned_setup(const RunConfig& config, const Dataset& source);
// What a trained model depends on: the training data and every training option.
Provenance training_provenance(const RunConfig& config, const RunData& data);
// Keeps (StageCache::Keep) a record of the model in model_path made under the budget rule's
// earlier rate-left edge, twice the floor, where its training took the decisions the rule takes
// now (decided_as_now) and the model's own record (<model>.provenance.json) still names that
// edge: hours of finished models need not be trained again for a change that decided nothing
// for them.
StageCache::Keep kept_under_earlier_edge(const RunConfig& config, const Provenance& wanted,
                                         const std::string& model_path,
                                         const TrainingOptions& options);
// How a model was trained, from the record its file keeps (path names it in errors): history,
// best round, convergence, throughput and its fraction of the GEMM peak.
TrainingSummary training_summary(const LearnedModel& model, const std::string& path,
                                 const LearnedSetup& setup);
LearnedResults run_learned(const Context& context, const std::string& augment,
                           const LearnedSetup& setup, const RunData& data,
                           const Reconstruction& reconstruction, const NoisyFrames& noisy);

// The sweep's sizes on a training split of `train_count` frames, ascending, each once: a size
// above the split is the whole split, whose converged models are the main runs' (the standard
// preset's 5,500 on a split of 5,459 frames was left out before).
std::vector<int> sweep_sizes(const std::vector<int>& sizes, int train_count);

// 5. Data efficiency (the paper's Fig. 8): test scores against the training-set size, at each
// of `sizes` (the configuration's, or a shard's share of them; sweep_sizes applied).
std::vector<EfficiencyPoint> run_sweep(const Context& context, const LearnedSetup& setup,
                                       const RunData& data, const Reconstruction& reconstruction,
                                       const RunResults& main_runs, const std::vector<int>& sizes);

// 6. Real presses (measured_stage.cpp): with --measured and --calibration, every method scored on
// where it puts each press of the measured set, tuned on the calibration set's presses or in
// simulation, the learned model also fine-tuned on the first presses of the calibration set.
std::vector<MeasuredRow> run_measured(const Context& context, const RunData& data,
                                      const Reconstruction& reconstruction,
                                      const LearnedSetup& setup,
                                      const std::vector<std::string>& augments,
                                      const RunResults& simulated);
// The simulation like the sensor (like_sensor.cpp): simulated frames that hold one touch, split
// in two (one to tune on, one to score), with the channel gains and noise measured on the
// calibration set's repeated references; none (said in the log) when that set has no paired
// references.
struct LikeSensor {
  SampleMatrix validation_frames, validation_labels, test_frames;
  std::vector<std::vector<PressTouch>> validation_touches, test_touches;
  SensorNoise noise;  // measured on the references
  double misfit = 0;  // the real frames' misfit to the model, over the reference's RMS
  double signal = 0;  // the test frames' median RMS over the reference's RMS, as noise.signal
};
std::optional<LikeSensor> like_sensor(const Context& context, const RunData& data,
                                      const std::shared_ptr<const LinearProblem>& problem,
                                      const SampleMatrix& cal_frames);
// The median centre error of `method` on the test frames like the sensor, its presses put by
// `rule`.
double like_sensor_median(const Reconstructor& method, const PixelGrid& grid,
                          const LikeSensor& like, const PressRule& rule);
// The press fit of the run's sensor file (calibrate --presses --out), if it has one; InputError
// when it was fitted on the scored presses. Checked before the simulated stages too.
std::optional<SensorPressFit> sensor_press_fit(const RunConfig& config);
// Where the run keeps the learned model trained with `augment` (models/dnn_<augment>.pt).
std::string learned_model_path(const Context& context, const std::string& augment);

// The touch metrics of a method at one SNR (touch_stage.cpp): the blob threshold chosen on the
// first touch_validation_frames of `validation_frames` as the method reconstructs them, the test
// images scored with it. Not scored (frames 0) when the test or validation frames lack circles.
TouchScores touch_scores(const Context& context, const RunData& data,
                         const Reconstruction& reconstruction, const Reconstructor& method,
                         const SampleMatrix& validation_frames, const SampleMatrix& test_images);
bool scores_touches(const RunData& data);
// The same for a method that finds circles (the shape fit): its test circles as found, no blobs.
TouchScores circle_touch_scores(const RunData& data, const Reconstruction& reconstruction,
                                const std::vector<std::vector<Circle>>& test_circles);

// The row of one evaluation (quality, latency and settings); labels may be empty.
// `circles` gets the circles of a method that finds them (empty otherwise).
ResultRow evaluate_row(const Reconstructor& method, const SampleMatrix& frames,
                       const SampleMatrix& labels, const PixelGrid& grid, int timed_frames,
                       SampleMatrix* images = nullptr,
                       std::vector<std::vector<Circle>>* circles = nullptr);
std::vector<Eigen::VectorXd> first_images(const SampleMatrix& images, int count);
// "CC 0.812, RE 0.634" (then the touch metrics when scored) or "no labels", for the log.
std::string quality(const ResultRow& row);

// A method's results in the stage cache (the rows in results.json's form, the images as float).
nlohmann::json to_json(const MethodResults& results);
MethodResults method_results_from(const nlohmann::json& j);

}  // namespace eitbench::run
