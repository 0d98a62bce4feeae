#pragma once
// The KTC benchmark (docs/ktc.md#the-benchmark): every model-based method on KTC2023's four
// training samples at each of the seven levels, its regularisation swept over its candidates and
// its segmentation chosen among three-class Otsu and fixed levels, scored by the challenge's score.
// Each sample is scored held out: with the setting tuned on the other three samples (all levels),
// never on itself; the setting tuned on all four is what `eitbench ktc --from RUN` applies.
#include <cstdint>
#include <string>
#include <vector>

#include "eitbench/bench/ktc/ktc_learned.h"
#include "eitbench/bench/ktc/ktc_method.h"

namespace eitbench {

// The levels rule's fractions tried, each for the resistive and the conductive class apart.
const std::vector<double>& ktc_level_fractions();

// One reconstruction's score under every segmentation rule tried.
struct KtcFrameScores {
  double otsu = 0;  // the whole score with three-class Otsu
  // The SSIM of each class's mask at each of ktc_level_fractions(): the levels rule's score for
  // fractions (r, c) is (resistive[r] + conductive[c]) / 2, each class apart.
  std::vector<double> resistive, conductive;
};

// A method's setting: its regularisation and its segmentation.
struct KtcChoice {
  int candidate = 0;  // index into the candidates
  double lambda = 0;
  double noise_relative = 0;  // the data term's noise model (KtcNoise::relative) it was tuned at
  SegmentationRule rule;
  double tuning_score = 0;  // the summed score on the samples it was tuned on
  // How the rule's kind was chosen (choose_ktc_rules): each kind's score on the tuning samples,
  // each sample scored with the setting tuned on the others. Zero where the kind was imposed.
  double nested_otsu = 0, nested_levels = 0;
};

// The segmentation rules a tuning may pick from.
enum class KtcRules { otsu, levels, either };

struct KtcMethodResult {
  std::string method;
  // The candidates: each a regularisation weight (candidates) at a noise model of the data term
  // (candidate_noise: KtcNoise::relative, the floor the run's), every weight at every noise.
  std::vector<double> candidates, candidate_noise;
  std::vector<int> levels, samples;  // the KTC levels and sample numbers, in the order below
  // scores[candidate][level][sample]
  std::vector<std::vector<std::vector<KtcFrameScores>>> scores;
  std::vector<std::vector<std::vector<double>>> milliseconds;  // each reconstruction's time
  std::vector<double> setup_seconds;                           // per level: building the method
  KtcChoice best;                                              // tuned on every sample
  std::vector<KtcChoice> held_out_choice;                      // per sample: tuned on the others
  // [level][sample]: the score with `best` (in sample) and with the sample's held-out choice.
  std::vector<std::vector<double>> in_sample, held_out;
  // The same with Otsu only (the challenge's baseline segmentation), lambda tuned alike.
  std::vector<std::vector<double>> held_out_otsu;
  // Tuned on simulated tanks instead (KtcRunOptions::tuning_tanks; all three empty for a method
  // not so tuned): every candidate's scores on the tanks, [candidate][level][tank]; the setting
  // they choose (choose_ktc_rules on the tanks); and each sample's score with it, [level][sample].
  // Nothing of the samples is tuned on: every sample is held out.
  std::vector<std::vector<std::vector<KtcFrameScores>>> simulated;
  KtcChoice simulation_choice;
  std::vector<std::vector<double>> tuned_on_simulation;
  // Tuned on the other samples and the tanks together (empty without tanks): per sample, the
  // setting chosen on them (tune_jointly), and each sample's score with its own, [level][sample];
  // the setting chosen on every sample and the tanks (what `eitbench ktc --setting joint`
  // applies), and each sample's score with it (in sample).
  std::vector<KtcChoice> joint_choice;
  std::vector<std::vector<double>> tuned_jointly;
  KtcChoice joint_best;
  std::vector<std::vector<double>> joint_in_sample;
  // Images (the method's grid) with `best`, [level][sample], for the figures.
  std::vector<std::vector<Eigen::VectorXd>> images;
  double median_ms = 0;  // per reconstruction at best's lambda
};

// The best setting on `samples` (indices into result.samples), every level summed, among `rules`;
// with `only_candidate` >= 0 at that candidate only. Ties go to the earlier candidate, Otsu and
// smaller fractions. `weights`, one a sample where given, weigh each sample's scores in the sum.
KtcChoice tune_ktc(const KtcMethodResult& result, const std::vector<int>& samples, KtcRules rules,
                   int only_candidate = -1, const std::vector<double>& weights = {});
// The setting tuned on `samples` with its rule's kind chosen as the setting itself is, on data it
// was not tuned on (nested): each kind, Otsu or the levels rule, is tuned on all of `samples` but
// one and scored on the one left out, each in turn; the kind that scores more is tuned on all of
// them. The levels rule tunes two fractions more than Otsu, and on three samples it can win every
// tuning and still lose the sample left out. Ties, and fewer than two samples, go to Otsu.
// `weights` as tune_ktc's: each sample left out counts with its weight.
KtcChoice choose_ktc_rules(const KtcMethodResult& result, const std::vector<int>& samples,
                           const std::vector<double>& weights = {});
// A [level][sample] table of scores summed as the challenge sums them: each level's mean over the
// samples times 3 (its three targets a level), then over the levels (at most 21 for seven).
double ktc_level_total(const std::vector<double>& samples);
double ktc_total(const std::vector<std::vector<double>>& table);
// The score of sample `s` at level index `l` with `choice`.
double ktc_choice_score(const KtcMethodResult& result, const KtcChoice& choice, int l, int s);
// Fills best, held_out_choice, in_sample, held_out and held_out_otsu from the scores: best and
// each held-out choice by choose_ktc_rules.
void tune_and_hold_out(KtcMethodResult& result);

// Fills simulation_choice and tuned_on_simulation from `simulated` (nothing when it is empty): the
// setting chosen on the simulated tanks as `best` is on the samples, every sample scored with it.
void tune_on_simulation(KtcMethodResult& result);
// Fills joint_choice, tuned_jointly, joint_best and joint_in_sample from `scores` and `simulated`
// (nothing without tanks): each sample scored with the setting choose_ktc_rules picks on the other
// samples and the tanks together, the other samples weighing one half and the tanks the other (each
// alike within its half), so that neither source's count decides; with a single sample, the tanks
// alone.
void tune_jointly(KtcMethodResult& result);
// The scores of one image (on KTC's grid) against one truth under every rule.
KtcFrameScores score_every_rule(const Eigen::MatrixXd& ktc_image, const KtcScorer& truth);

// The KTC methods that reconstruct in one linear step (MethodSpec::one_step), in KTC's order.
std::vector<std::string> ktc_one_step_names();
struct KtcRunOptions {
  std::string data;  // a folder of ref.mat, dataN.mat and trueN.mat
  std::string out;   // the run folder
  std::vector<std::string> methods = ktc_method_names();
  std::vector<int> levels{1, 2, 3, 4, 5, 6, 7};
  KtcTankOptions tank;
  KtcNoise noise;  // the data term's noise for the iterative methods and the learned rows
  // The noise models every method (ktc_sweeps_noise) is tuned over like its weight:
  // KtcNoise::relative from the challenge's baseline (5e-4) to a data term weighted by the
  // reference's values alone (5e-2, where the floor no longer counts), each with noise.floor.
  // GREIT and the learned rows keep `noise`.
  std::vector<double> noise_sweep{5e-4, 5e-3, 5e-2};
  int grid = 64;
  // Simulated tanks the methods in `simulation_tuned` are tuned on too (docs/ktc.md): drawn as
  // the learned rows' training tanks are (learned's contrast band, the reference's measured noise)
  // from a stream of their own (tuning_seed), on a mesh finer than the reconstructions' (fine
  // where the tank's is coarse or medium). 0: none. Each tank costs what a sample does.
  int tuning_tanks = 16;
  std::uint64_t tuning_seed = 1;
  // Each tank value's noise (V, one standard deviation). 0: the reference's measured noise
  // (repeated_pattern_noise), as the learned rows' tanks have. A larger value stands in for the
  // real tank's model error, which the simulated frames lack (docs/ktc.md).
  double tuning_noise = 0;
  // By default the one-step methods (a reconstruction in milliseconds); an iterative one costs
  // its seconds a frame again for each tank, candidate and level. `eitbench ktc --from RUN`
  // applies the samples' setting (best) unless told --setting simulation.
  std::vector<std::string> simulation_tuned = ktc_one_step_names();
  KtcLearnedOptions learned;  // the learned rows (none without arms)
  bool quiet = false;

  // Whether `method` is tuned on simulated tanks: tanks are drawn and simulation_tuned names it.
  bool tunes_on_simulation(const std::string& method) const;
  // Whether the run draws tuning tanks at all: some method of `methods` is tuned on them.
  bool draws_tuning_tanks() const;

  // InputError naming the flag: the data folder (ref.mat, and dataN.mat each with its trueN.mat),
  // a level outside 1 ... 7 or given twice, a method that is no KTC one or given twice (in
  // methods or simulation_tuned), the grid, the tank, the noise, the tuning tanks' count, the
  // learned rows' options.
  void validate() const;
};

// Whether a KTC run tunes `method`'s noise model (KtcRunOptions::noise_sweep): every method whose
// image the noise model changes, all but GREIT.
bool ktc_sweeps_noise(const std::string& method);
// The noise models `method` is tuned over in a run: noise_sweep or noise.relative alone.
std::vector<double> ktc_noise_candidates(const std::string& method, const KtcRunOptions& options);

// Every file of a KTC run, read and checked before anything is written.
struct KtcInputs {
  std::string reference_path, reference_hash;
  KtcMeasurement reference;
  struct Sample {
    int number;
    KtcMeasurement measurement;
    ClassImage truth;
  };
  std::vector<Sample> samples;
};
// InputError naming the file and field for a bad file, or a sample of other patterns than ref.mat.
KtcInputs load_ktc_inputs(const KtcRunOptions& options);

struct KtcRunResults {
  KtcRunOptions options;
  KtcTank tank;                // calibrated
  std::string reference_hash;  // of ref.mat's bytes (content_hash.h)
  double calibration_seconds = 0;
  std::vector<KtcMethodResult> methods;
  KtcLearnedResults learned;       // its arms empty when none were asked
  std::vector<ClassImage> truths;  // per sample
  std::vector<int> samples;        // KTC's sample numbers
  // Each sample's model misfit at level 1 (KtcContrastFits::own_misfits): what a tuning tank's
  // noise would need to stand for (ktc_misfit_noise).
  std::vector<KtcMisfit> misfits;
  // How the tuning tanks were drawn (KtcRunOptions::tuning_tanks; tanks 0 when none were): the
  // simulation's seed, the tank's mesh and each value's noise (V).
  struct Tuning {
    int tanks = 0;
    unsigned seed = 0;
    KtcTankOptions tank;
    double noise = 0;
  } tuning;
};

// The whole run on the loaded inputs: calibrate, sweep every method, tune, hold out, then train
// and score the learned models (their model files the only thing written, into options.out).
// Each model-based reconstruction is timed while another level runs beside it (one a core).
KtcRunResults run_ktc(const KtcRunOptions& options, const KtcInputs& inputs);

}  // namespace eitbench
