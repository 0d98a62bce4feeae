#include "eitbench/bench/ktc/ktc_run.h"

#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <mutex>
#include <numeric>
#include <stdexcept>

#include "eitbench/bench/io/content_hash.h"
#include "eitbench/bench/ktc/tank_simulation.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/bench/support/progress.h"
#include "eitbench/bench/support/timing.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {
// About 3 MB a tank (its truth's masks and windowed moments, 256 x 256 each) and its scores for
// every candidate and level: 1.5 GB at the most.
constexpr int kMaxTuningTanks = 500;
}  // namespace

const std::vector<double>& ktc_level_fractions() {
  static const std::vector<double> f = [] {
    std::vector<double> v;
    for (int k = 1; k <= 19; ++k) v.push_back(0.05 * k);
    return v;
  }();
  return f;
}

KtcFrameScores score_every_rule(const Eigen::MatrixXd& x, const KtcScorer& truth) {
  KtcFrameScores s;
  s.otsu = truth(segment(x, {})).total();
  double largest = 0;
  for (Eigen::Index k = 0; k < x.size(); ++k)
    if (std::isfinite(x.data()[k])) largest = std::max(largest, std::abs(x.data()[k]));
  for (double f : ktc_level_fractions()) {
    // NaN (outside the tank) compares false: water, as segment() has it; a blank image is water.
    const Eigen::MatrixXd none = Eigen::MatrixXd::Zero(x.rows(), x.cols());
    const Eigen::MatrixXd resistive =
        largest == 0 ? none : (x.array() >= f * largest).cast<double>().matrix();
    const Eigen::MatrixXd conductive =
        largest == 0 ? none : (x.array() <= -f * largest).cast<double>().matrix();
    s.resistive.push_back(truth.ssim(1, resistive));
    s.conductive.push_back(truth.ssim(2, conductive));
  }
  return s;
}

double ktc_choice_score(const KtcMethodResult& r, const KtcChoice& c, int l, int s) {
  const KtcFrameScores& f = r.scores[static_cast<std::size_t>(c.candidate)]
                                    [static_cast<std::size_t>(l)][static_cast<std::size_t>(s)];
  if (c.rule.kind == SegmentationKind::otsu) return f.otsu;
  const auto& fr = ktc_level_fractions();
  auto index = [&](double v) {
    return static_cast<std::size_t>(
        std::min_element(fr.begin(), fr.end(),
                         [v](double a, double b) { return std::abs(a - v) < std::abs(b - v); }) -
        fr.begin());
  };
  return 0.5 * (f.resistive[index(c.rule.resistive)] + f.conductive[index(c.rule.conductive)]);
}

KtcChoice tune_ktc(const KtcMethodResult& r, const std::vector<int>& samples, KtcRules rules,
                   int only_candidate, const std::vector<double>& weights) {
  if (!weights.empty() && weights.size() != samples.size())
    throw std::invalid_argument("tune_ktc: a weight for each sample or none");
  KtcChoice best;
  best.tuning_score = -INFINITY;
  const auto& fr = ktc_level_fractions();
  for (std::size_t c = 0; c < r.candidates.size(); ++c) {
    if (only_candidate >= 0 && c != static_cast<std::size_t>(only_candidate)) continue;
    double otsu = 0;
    std::vector<double> res(fr.size(), 0.0), con(fr.size(), 0.0);
    for (std::size_t l = 0; l < r.levels.size(); ++l)
      for (std::size_t i = 0; i < samples.size(); ++i) {
        const KtcFrameScores& f = r.scores[c][l][static_cast<std::size_t>(samples[i])];
        const double w = weights.empty() ? 1.0 : weights[i];
        otsu += w * f.otsu;
        for (std::size_t k = 0; k < fr.size(); ++k)
          res[k] += w * f.resistive[k], con[k] += w * f.conductive[k];
      }
    auto take = [&](double score, SegmentationRule rule) {
      if (score > best.tuning_score + 1e-12) {
        best.candidate = static_cast<int>(c);
        best.lambda = r.candidates[c];
        best.noise_relative = c < r.candidate_noise.size() ? r.candidate_noise[c] : 0.0;
        best.rule = rule;
        best.tuning_score = score;
      }
    };
    if (rules != KtcRules::levels) take(otsu, {});
    if (rules == KtcRules::otsu) continue;
    // The two classes' masks never overlap under the levels rule: each fraction apart.
    const auto ir = std::max_element(res.begin(), res.end()) - res.begin();
    const auto ic = std::max_element(con.begin(), con.end()) - con.begin();
    take(0.5 * (res[static_cast<std::size_t>(ir)] + con[static_cast<std::size_t>(ic)]),
         {SegmentationKind::levels, fr[static_cast<std::size_t>(ir)],
          fr[static_cast<std::size_t>(ic)]});
  }
  return best;
}

double ktc_level_total(const std::vector<double>& samples) {
  double sum = 0;
  for (double v : samples) sum += v;
  return samples.empty() ? 0 : sum * 3.0 / static_cast<double>(samples.size());
}

double ktc_total(const std::vector<std::vector<double>>& table) {
  double sum = 0;
  for (const auto& level : table) sum += ktc_level_total(level);
  return sum;
}

KtcChoice choose_ktc_rules(const KtcMethodResult& r, const std::vector<int>& samples,
                           const std::vector<double>& weights) {
  double nested[2] = {0, 0};  // Otsu, levels
  if (samples.size() >= 2)
    for (std::size_t t = 0; t < samples.size(); ++t) {
      std::vector<int> others = samples;
      others.erase(others.begin() + static_cast<std::ptrdiff_t>(t));
      std::vector<double> other_weights = weights;
      if (!weights.empty())
        other_weights.erase(other_weights.begin() + static_cast<std::ptrdiff_t>(t));
      const double w = weights.empty() ? 1.0 : weights[t];
      for (int k = 0; k < 2; ++k) {
        const KtcChoice c =
            tune_ktc(r, others, k == 0 ? KtcRules::otsu : KtcRules::levels, -1, other_weights);
        for (std::size_t l = 0; l < r.levels.size(); ++l)
          nested[k] += w * ktc_choice_score(r, c, static_cast<int>(l), samples[t]);
      }
    }
  KtcChoice chosen = tune_ktc(
      r, samples, nested[1] > nested[0] + 1e-12 ? KtcRules::levels : KtcRules::otsu, -1, weights);
  chosen.nested_otsu = nested[0], chosen.nested_levels = nested[1];
  return chosen;
}

void tune_and_hold_out(KtcMethodResult& r) {
  const int S = static_cast<int>(r.samples.size()), L = static_cast<int>(r.levels.size());
  std::vector<int> all(static_cast<std::size_t>(S));
  for (int s = 0; s < S; ++s) all[static_cast<std::size_t>(s)] = s;
  r.best = choose_ktc_rules(r, all);
  r.in_sample.assign(static_cast<std::size_t>(L), std::vector<double>(static_cast<std::size_t>(S)));
  r.held_out = r.held_out_otsu = r.in_sample;
  r.held_out_choice.clear();
  for (int s = 0; s < S; ++s) {
    std::vector<int> others;
    for (int o = 0; o < S; ++o)
      if (o != s) others.push_back(o);
    // With a single sample there is nothing else to tune on: in sample, and the report says so.
    if (others.empty()) others = all;
    const KtcChoice held = choose_ktc_rules(r, others), otsu = tune_ktc(r, others, KtcRules::otsu);
    r.held_out_choice.push_back(held);
    for (int l = 0; l < L; ++l) {
      r.in_sample[static_cast<std::size_t>(l)][static_cast<std::size_t>(s)] =
          ktc_choice_score(r, r.best, l, s);
      r.held_out[static_cast<std::size_t>(l)][static_cast<std::size_t>(s)] =
          ktc_choice_score(r, held, l, s);
      r.held_out_otsu[static_cast<std::size_t>(l)][static_cast<std::size_t>(s)] =
          ktc_choice_score(r, otsu, l, s);
    }
  }
}

namespace {
// A result with r's candidates and levels and `scores` in the samples' place: tanks to tune on.
KtcMethodResult with_scores(const KtcMethodResult& r,
                            std::vector<std::vector<std::vector<KtcFrameScores>>> scores) {
  KtcMethodResult out;
  out.candidates = r.candidates;
  out.candidate_noise = r.candidate_noise;
  out.levels = r.levels;
  out.scores = std::move(scores);
  return out;
}

// Every sample of r scored with one setting, [level][sample].
std::vector<std::vector<double>> every_sample_with(const KtcMethodResult& r, const KtcChoice& c) {
  const std::size_t L = r.levels.size(), S = r.samples.size();
  std::vector<std::vector<double>> table(L, std::vector<double>(S));
  for (std::size_t l = 0; l < L; ++l)
    for (std::size_t s = 0; s < S; ++s)
      table[l][s] = ktc_choice_score(r, c, static_cast<int>(l), static_cast<int>(s));
  return table;
}

// The setting choose_ktc_rules picks on the samples of `pool` but `left_out` (none: -1) and on its
// tanks (the rest), the samples weighing one half and the tanks the other, each alike within its
// half; with no sample, the tanks alone.
KtcChoice choose_on_samples_and_tanks(const KtcMethodResult& pool, std::size_t S, int left_out) {
  const std::size_t T = pool.scores.front().front().size() - S;
  std::vector<int> members;
  for (std::size_t o = 0; o < S; ++o)
    if (static_cast<int>(o) != left_out) members.push_back(static_cast<int>(o));
  const double on_samples = members.empty() ? 0.0 : 0.5 / static_cast<double>(members.size());
  std::vector<double> weights(members.size(), on_samples);
  const double on_tanks = (members.empty() ? 1.0 : 0.5) / static_cast<double>(T);
  for (std::size_t t = 0; t < T; ++t)
    members.push_back(static_cast<int>(S + t)), weights.push_back(on_tanks);
  return choose_ktc_rules(pool, members, weights);
}
}  // namespace

void tune_on_simulation(KtcMethodResult& r) {
  r.tuned_on_simulation.clear();
  if (r.simulated.empty() || r.simulated.front().empty()) return;
  std::vector<int> all(r.simulated.front().front().size());
  std::iota(all.begin(), all.end(), 0);
  r.simulation_choice = choose_ktc_rules(with_scores(r, r.simulated), all);
  r.tuned_on_simulation = every_sample_with(r, r.simulation_choice);
}

void tune_jointly(KtcMethodResult& r) {
  r.joint_choice.clear(), r.tuned_jointly.clear(), r.joint_in_sample.clear();
  if (r.simulated.empty() || r.simulated.front().empty()) return;
  const std::size_t C = r.candidates.size(), L = r.levels.size(), S = r.samples.size();
  KtcMethodResult pool = with_scores(r, r.scores);  // the samples, then the tanks
  for (std::size_t c = 0; c < C; ++c)
    for (std::size_t l = 0; l < L; ++l)
      pool.scores[c][l].insert(pool.scores[c][l].end(), r.simulated[c][l].begin(),
                               r.simulated[c][l].end());
  r.joint_best = choose_on_samples_and_tanks(pool, S, -1);
  r.joint_in_sample = every_sample_with(r, r.joint_best);
  r.tuned_jointly.assign(L, std::vector<double>(S));
  for (std::size_t s = 0; s < S; ++s) {
    r.joint_choice.push_back(choose_on_samples_and_tanks(pool, S, static_cast<int>(s)));
    for (std::size_t l = 0; l < L; ++l)
      r.tuned_jointly[l][s] =
          ktc_choice_score(r, r.joint_choice.back(), static_cast<int>(l), static_cast<int>(s));
  }
}

std::vector<std::string> ktc_one_step_names() {
  const std::vector<std::string> one_step = method_names_with(&MethodSpec::one_step);
  std::vector<std::string> names;
  for (const std::string& m : ktc_method_names())
    if (std::find(one_step.begin(), one_step.end(), m) != one_step.end()) names.push_back(m);
  return names;
}

bool KtcRunOptions::tunes_on_simulation(const std::string& method) const {
  return tuning_tanks > 0 && std::find(simulation_tuned.begin(), simulation_tuned.end(), method) !=
                                 simulation_tuned.end();
}

bool KtcRunOptions::draws_tuning_tanks() const {
  return std::any_of(methods.begin(), methods.end(),
                     [&](const std::string& m) { return tunes_on_simulation(m); });
}

void KtcRunOptions::validate() const {
  std::error_code ec;
  if (!std::filesystem::is_directory(data, ec))
    throw InputError("--ktc", "", "'" + data + "' is not a folder of KTC files");
  for (const auto& s : scan_ktc_folder(data).samples)  // ref.mat and dataN.mat there ...
    if (s.truth.empty())                               // ... each with its truth
      throw InputError(s.data, "",
                       "has no true" + std::to_string(s.number) +
                           ".mat beside it: the benchmark scores against the truth");
  if (levels.empty()) throw InputError("--levels", "", "needs at least one level");
  for (std::size_t k = 0; k < levels.size(); ++k) {
    ktc_removed_electrodes(levels[k]);  // InputError for a level outside 1 ... 7
    if (std::count(levels.begin(), levels.begin() + static_cast<std::ptrdiff_t>(k), levels[k]))
      throw InputError("--levels", "", "lists level " + std::to_string(levels[k]) + " twice");
  }
  if (methods.empty() && learned.arms.empty())
    throw InputError("--methods", "", "needs at least one method");
  for (std::size_t k = 0; k < methods.size(); ++k) {
    if (std::find(ktc_method_names().begin(), ktc_method_names().end(), methods[k]) ==
        ktc_method_names().end())
      throw InputError("--methods", "", "'" + methods[k] + "' is not a method the KTC run ranks");
    if (std::count(methods.begin(), methods.begin() + static_cast<std::ptrdiff_t>(k), methods[k]))
      throw InputError("--methods", "", "lists " + methods[k] + " twice");
  }
  for (std::size_t k = 0; k < simulation_tuned.size(); ++k) {
    const auto& name = simulation_tuned[k];
    if (std::find(ktc_method_names().begin(), ktc_method_names().end(), name) ==
        ktc_method_names().end())
      throw InputError("--tune-on-simulation", "",
                       "'" + name + "' is not a method the KTC run ranks");
    if (std::count(simulation_tuned.begin(),
                   simulation_tuned.begin() + static_cast<std::ptrdiff_t>(k), name))
      throw InputError("--tune-on-simulation", "", "lists " + name + " twice");
  }
  // Each tank keeps its truth's windowed moments (2 MB) and its scores for every candidate.
  if (tuning_tanks < 0 || tuning_tanks > kMaxTuningTanks)
    throw InputError("--tuning-tanks", "",
                     fmt::format("{} is out of range: 0 ... {}", tuning_tanks, kMaxTuningTanks));
  // A volt is over half the reference's largest value (1.6 V): no longer a noise.
  if (!(tuning_noise >= 0 && tuning_noise <= 1))
    throw InputError("--tuning-noise", "",
                     fmt::format("{} is out of range: 0 ... 1 V", tuning_noise));
  check_ktc_grid(grid);
  tank.validate();
  noise.validate();
  if (noise_sweep.empty()) throw InputError("--noise-sweep", "", "needs at least one value");
  for (std::size_t k = 0; k < noise_sweep.size(); ++k) {
    if (!KtcNoise{noise_sweep[k], noise.floor}.valid())
      throw InputError("--noise-sweep", "",
                       fmt::format("{:g} is no noise model: zero or more, finite, and not zero "
                                   "with --noise-floor 0",
                                   noise_sweep[k]));
    if (std::count(noise_sweep.begin(), noise_sweep.begin() + static_cast<std::ptrdiff_t>(k),
                   noise_sweep[k]))
      throw InputError("--noise-sweep", "", fmt::format("lists {:g} twice", noise_sweep[k]));
  }
  learned.validate();
}

bool ktc_sweeps_noise(const std::string& method) {
  ktc_candidates(method);  // a KTC method, or InputError
  // Every method whose image the noise model changes: not GREIT's (its own training frames set
  // its noise: the measured run's sweeps agreed at every model).
  return method != "greit";
}

std::vector<double> ktc_noise_candidates(const std::string& method, const KtcRunOptions& options) {
  return ktc_sweeps_noise(method) ? options.noise_sweep
                                  : std::vector<double>{options.noise.relative};
}

KtcInputs load_ktc_inputs(const KtcRunOptions& options) {
  options.validate();
  const KtcFolder folder = scan_ktc_folder(options.data);
  KtcInputs in;
  in.reference_path = folder.reference;
  in.reference = read_ktc_measurement(folder.reference);
  in.reference_hash = file_hash(folder.reference);
  for (const auto& s : folder.samples) {
    in.samples.push_back({s.number, read_ktc_measurement(s.data), read_ktc_truth(s.truth)});
    check_same_patterns(in.samples.back().measurement, in.reference.patterns);
  }
  return in;
}

namespace {

using Sample = KtcInputs::Sample;

// The simulated tanks a method is tuned on (KtcRunOptions::tuning_tanks): their difference frames
// (every value) and their truths on KTC's grid.
struct TuningTanks {
  Eigen::MatrixXd frames;  // tanks x values
  std::vector<KtcScorer> scorers;
  KtcRunResults::Tuning draw;  // how they were drawn, for the record
};

// The tanks are drawn as the learned rows' training tanks are, but on a finer mesh than the
// reconstructions' (the model that simulates is not the one that inverts) and from a stream of
// their own, so that they are none of the learned rows' tanks.
TuningTanks simulate_tuning_tanks(const KtcSetup& setup, const KtcMeasurement& reference,
                                  const KtcRunOptions& options) {
  KtcTankOptions finer = setup.tank.options;
  // A tank already on the fine mesh is simulated on one finer still (0.7 of its sizes).
  if (finer.density == MeshDensity::fine) finer.size_factor *= 0.7;
  finer.density = MeshDensity::fine;
  const KtcTank tank =
      ktc_tank_at(reference, finer, setup.tank.background, setup.tank.contact_impedances);
  KtcSimulationOptions so = ktc_training_simulation(options.learned, tank);
  so.samples = options.tuning_tanks;
  so.seed = static_cast<unsigned>(options.tuning_seed * 2654435761u + 12345u);
  so.grid = kKtcImageSize;
  so.orientation = setup.orientation;
  if (options.tuning_noise > 0) so.noise = options.tuning_noise;
  KtcSimulatedSet set = simulate_ktc_tanks(tank, so);
  TuningTanks t;
  t.frames = std::move(set.frames);
  // Where the reference lacks a value the samples' differences do too: so do the tanks'.
  for (Eigen::Index i = 0; i < t.frames.cols(); ++i)
    if (!std::isfinite(setup.tank.reference[i]))
      t.frames.col(i).setConstant(std::numeric_limits<double>::quiet_NaN());
  for (const ClassImage& label : set.labels) t.scorers.emplace_back(label);
  t.draw = {options.tuning_tanks, so.seed, finer, so.noise};
  return t;
}

// The tanks' frames at a level: the level's values missing (NaN), as the samples' are.
std::vector<Eigen::VectorXd> tank_frames_at(const TuningTanks* tanks,
                                            const CurrentPatterns& patterns, int level) {
  std::vector<Eigen::VectorXd> frames;
  for (Eigen::Index t = 0; tanks && t < tanks->frames.rows(); ++t)
    frames.push_back(ktc_level_frame(tanks->frames.row(t).transpose(), patterns, level));
  return frames;
}

// Every candidate's reconstructions of every sample at every level, scored: each regularisation
// weight at each of `noises` (KtcNoise::relative with setup's floor); and of every tuning tank
// where `tanks` is given (not timed).
KtcMethodResult sweep(const KtcSetup& setup, const KtcNoise& noise, const std::string& method,
                      const std::vector<double>& noises, const std::vector<Sample>& samples,
                      const std::vector<int>& levels, const std::vector<KtcScorer>& scorers,
                      const TuningTanks* tanks, Progress& progress, int& done) {
  std::mutex progress_mutex;  // done is counted from every level
  KtcMethodResult r;
  r.method = method;
  const std::vector<double>& weights = ktc_candidates(method);
  for (double n : noises)
    for (double w : weights) r.candidates.push_back(w), r.candidate_noise.push_back(n);
  r.levels = levels;
  for (const Sample& s : samples) r.samples.push_back(s.number);
  const std::size_t C = r.candidates.size(), L = levels.size(), S = samples.size();
  const std::size_t W = weights.size();
  r.scores.assign(C, std::vector<std::vector<KtcFrameScores>>(L, std::vector<KtcFrameScores>(S)));
  const std::size_t T = tanks ? static_cast<std::size_t>(tanks->frames.rows()) : 0;
  if (T > 0)
    r.simulated.assign(C,
                       std::vector<std::vector<KtcFrameScores>>(L, std::vector<KtcFrameScores>(T)));
  const CurrentPatterns& patterns = setup.tank.protocol->patterns();
  r.milliseconds.assign(C, std::vector<std::vector<double>>(L, std::vector<double>(S)));
  std::vector<std::vector<std::vector<Eigen::VectorXd>>> images(
      C, std::vector<std::vector<Eigen::VectorXd>>(L, std::vector<Eigen::VectorXd>(S)));
  r.setup_seconds.assign(L, 0.0);
  std::vector<KtcSetup> setups;  // one a noise model: the same tank and linear problem
  for (double n : noises) {
    setups.push_back(setup);
    setups.back().noise = KtcNoise{n, noise.floor}.of(setup.tank.reference);
  }
  // Levels in parallel, each with a method of its own (one pattern of present values) for each
  // noise model; the weights of a level in turn, as set_regularisation keeps what it precomputed.
  tbb::parallel_for(std::size_t(0), L, [&](std::size_t l) {
    std::vector<Eigen::VectorXd> frames;  // the level's frames: the noise model weighs them later
    for (const Sample& s : samples)
      frames.push_back(ktc_difference(s.measurement, setup, levels[l]));
    const std::vector<Eigen::VectorXd> tank_frames = tank_frames_at(tanks, patterns, levels[l]);
    for (std::size_t n = 0; n < noises.size(); ++n) {
      const KtcSetup& at = setups[n];
      const std::unique_ptr<MissingValues> m = make_ktc_method(at, method, weights.front());
      const auto t0 = std::chrono::steady_clock::now();
      m->method_for(m->present_values(frames.front()));  // build the level's method once
      if (n == 0) r.setup_seconds[l] = seconds_since(t0);
      for (std::size_t w = 0; w < W; ++w) {
        const std::size_t c = n * W + w;
        m->set_regularisation(weights[w], "candidate");
        for (std::size_t s = 0; s < S; ++s) {
          const auto start = std::chrono::steady_clock::now();
          images[c][l][s] = m->reconstruct(frames[s]);
          r.milliseconds[c][l][s] = 1e3 * seconds_since(start);
          r.scores[c][l][s] = score_every_rule(ktc_image(at, images[c][l][s]), scorers[s]);
        }
        for (std::size_t t = 0; t < T; ++t)
          r.simulated[c][l][t] =
              score_every_rule(ktc_image(at, m->reconstruct(tank_frames[t])), tanks->scorers[t]);
        const std::lock_guard<std::mutex> lock(progress_mutex);
        progress.update(++done, method + " level " + std::to_string(levels[l]));
      }
    }
  });
  tune_and_hold_out(r);
  tune_on_simulation(r);
  tune_jointly(r);
  r.images = images[static_cast<std::size_t>(r.best.candidate)];
  std::vector<double> ms;
  for (const auto& level : r.milliseconds[static_cast<std::size_t>(r.best.candidate)])
    ms.insert(ms.end(), level.begin(), level.end());
  std::nth_element(ms.begin(), ms.begin() + static_cast<std::ptrdiff_t>(ms.size() / 2), ms.end());
  r.median_ms = ms[ms.size() / 2];
  return r;
}

// The contrasts fitted to each sample's change at level 1 against the model of its truth: the
// model misfits, and the learned rows' contrast band's check.
KtcContrastFits fit_samples(const KtcSetup& setup, const std::vector<Sample>& samples) {
  std::vector<Eigen::VectorXd> changes;
  std::vector<ClassImage> truths;
  for (const Sample& s : samples)
    changes.push_back(ktc_difference(s.measurement, setup, 1)), truths.push_back(s.truth);
  return fit_ktc_contrasts_held_out(setup.tank, changes, truths, setup.orientation);
}

// Each sample's misfit, and the tanks' noise it implies with each sample held out, printed: the
// figures --tuning-noise can be set from.
void print_misfits(const std::vector<KtcMisfit>& m, const std::vector<Sample>& samples) {
  for (std::size_t k = 0; k < m.size(); ++k)
    fmt::print(stderr,
               "sample {}: the model of its truth misses {:.1f} % of its change, {:.2f} mV a "
               "value; without it the tanks' noise would be {:.2f} mV\n",
               samples[k].number, 100 * m[k].relative, 1e3 * m[k].rms,
               1e3 * ktc_misfit_noise(m, k));
}

}  // namespace

KtcRunResults run_ktc(const KtcRunOptions& options, const KtcInputs& in) {
  options.validate();
  KtcRunResults out;
  out.options = options;
  out.reference_hash = in.reference_hash;
  for (const Sample& s : in.samples) out.samples.push_back(s.number), out.truths.push_back(s.truth);
  if (!options.quiet) fmt::print(stderr, "calibrating the tank to {} ...\n", in.reference_path);
  const auto t0 = std::chrono::steady_clock::now();
  KtcSetup setup =
      make_ktc_setup(calibrate_ktc_tank(in.reference, options.tank), options.grid, options.noise);
  out.calibration_seconds = seconds_since(t0);
  if (!options.quiet)
    fmt::print(stderr,
               "tank: sigma_0 {:.4g}, contact impedances {:.3g} ... {:.3g}, residual {:.2f} % "
               "({:.0f} s)\n",
               setup.tank.background, setup.tank.contact_impedances.minCoeff(),
               setup.tank.contact_impedances.maxCoeff(), 100 * setup.tank.relative_residual,
               out.calibration_seconds);
  const std::vector<Sample>& samples = in.samples;
  std::vector<KtcScorer> scorers;
  for (const Sample& s : samples) scorers.emplace_back(s.truth);
  const KtcContrastFits fits = fit_samples(setup, samples);
  out.misfits = fits.own_misfits();
  if (!options.quiet) print_misfits(out.misfits, samples);
  int total = 0, done = 0;
  for (const std::string& m : options.methods)
    total += static_cast<int>(ktc_candidates(m).size() * ktc_noise_candidates(m, options).size() *
                              options.levels.size());
  TuningTanks tanks;
  if (options.draws_tuning_tanks()) {
    if (!options.quiet)
      fmt::print(stderr, "simulating {} tanks to tune on ...\n", options.tuning_tanks);
    tanks = simulate_tuning_tanks(setup, in.reference, options);
    out.tuning = tanks.draw;
  }
  Progress progress("KTC sweep", total, options.quiet);
  for (const std::string& m : options.methods)
    out.methods.push_back(sweep(setup, options.noise, m, ktc_noise_candidates(m, options), samples,
                                options.levels, scorers,
                                options.tunes_on_simulation(m) ? &tanks : nullptr, progress, done));
  progress.finish();
  out.tank = setup.tank;
  if (!options.learned.arms.empty()) {
    std::vector<KtcMeasurement> measurements;
    for (const Sample& s : samples) measurements.push_back(s.measurement);
    out.learned = run_ktc_learned(setup, measurements, out.truths, fits, options.levels,
                                  options.learned, options.out, options.quiet);
  }
  return out;
}

}  // namespace eitbench
