#include "eitbench/bench/benchmark_run.h"

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "eitbench/bench/dataset.h"
#include "eitbench/bench/figures.h"
#include "eitbench/bench/io.h"
#include "eitbench/bench/machine.h"
#include "eitbench/bench/measurements.h"
#include "eitbench/bench/metrics.h"
#include "eitbench/bench/model_file.h"
#include "eitbench/bench/noise.h"
#include "eitbench/bench/progress.h"
#include "eitbench/bench/reconstructors.h"
#include "eitbench/bench/report.h"
#include "eitbench/bench/simulate.h"
#include "eitbench/bench/timing.h"
#include "eitbench/bench/training_data.h"
#include "eitbench/bench/training_run.h"
#include "eitbench/bench/version.h"
#include "eitbench/jacobian.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace fs = std::filesystem;
using nlohmann::json;

RunConfig RunConfig::for_preset(const std::string& preset) {
  RunConfig c;
  c.preset = preset;
  c.snrs = {INFINITY, 50, 40, 30};
  c.methods = {"tikhonov", "noser", "laplace", "greit", "gn", "tv"};
  c.augments = {"none", "rotations", "d16", "paper"};
  c.efficiency_epochs = 0, c.efficiency_steps = 0;  // the main runs' budgets
  if (preset == "tiny") {                           // the test suite's: every code path in seconds
    c.mesh = c.simulation = MeshDensity::coarse;
    c.epochs = 3, c.batch = 16;
    c.efficiency_sizes = {15, 30, 60};
    c.sweep_frames = 3, c.timed_frames = 3, c.figure_samples = 4;
  } else if (preset == "quick") {  // under 15 minutes on 2 cores
    c.efficiency_sizes = {250, 500, 1000, 2000};
  } else if (preset == "standard") {
    c.epochs = 40;
    c.efficiency_sizes = {350, 700, 1400, 2800, 5500};
    c.sweep_frames = 20, c.timed_frames = 50;
  } else if (preset == "paper") {  // the paper's protocol: GPU advised, resumable
    c.model = "paper";
    c.device = "auto";
    c.epochs = 300, c.batch = 512, c.learning_rate = 1e-4;
    c.efficiency_sizes = {700, 1400, 2800, 5600, 11200, 21833};
    c.sweep_frames = 20, c.timed_frames = 100;
  } else {
    throw InputError("--preset", "",
                     "unknown preset '" + preset + "' (tiny, quick, standard, paper)");
  }
  return c;
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Frames (and labels) of some rows of a data set.
struct Frames {
  SampleMatrix frames, labels;
};
Frames rows_of(const Dataset& d, const std::vector<int>& rows) {
  Frames f;
  f.frames.resize(static_cast<Eigen::Index>(rows.size()), d.differences.cols());
  f.labels.resize(static_cast<Eigen::Index>(rows.size()), d.labels.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    f.frames.row(k) = d.differences.row(rows[k]);
    if (d.has_labels()) f.labels.row(k) = d.labels.row(rows[k]);
  }
  return f;
}

// Finished stages of the run, one JSON file each, so that --resume skips them.
class Stages {
 public:
  Stages(fs::path folder, bool resume) : folder_(std::move(folder)), resume_(resume) {
    fs::create_directories(folder_);
  }
  bool find(const std::string& name, json& out) const {
    const fs::path p = folder_ / (name + ".json");
    if (!resume_ || !fs::exists(p)) return false;
    try {
      std::ifstream in(p);
      out = json::parse(in);
      return true;
    } catch (const json::exception&) {
      return false;  // unreadable: the stage runs again
    }
  }
  void save(const std::string& name, const json& value) const {
    write_text_atomically((folder_ / (name + ".json")).string(),
                          [&](std::ostream& o) { o << value.dump() << '\n'; });
  }

 private:
  fs::path folder_;
  bool resume_;
};

json row_json(const ResultRow& r) {
  auto num = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  return {{"method", r.method},      {"augment", r.augment},
          {"snr", num(r.snr_db)},    {"cc", num(r.cc)},
          {"re", num(r.re)},         {"ssim", num(r.ssim)},
          {"mse", num(r.mse)},       {"cc_std", num(r.cc_std)},
          {"re_std", num(r.re_std)}, {"median", r.latency_median_ms},
          {"p95", r.latency_p95_ms}, {"setup", r.setup_s},
          {"frames", r.frames},      {"settings", r.settings}};
}
ResultRow row_from(const json& j) {
  auto num = [](const json& v) { return v.is_null() ? NAN : v.get<double>(); };
  ResultRow r;
  r.method = j.at("method").get<std::string>();
  r.augment = j.at("augment").get<std::string>();
  r.snr_db = j.at("snr").is_null() ? INFINITY : j.at("snr").get<double>();
  r.cc = num(j.at("cc")), r.re = num(j.at("re")), r.ssim = num(j.at("ssim"));
  r.mse = num(j.at("mse")), r.cc_std = num(j.at("cc_std")), r.re_std = num(j.at("re_std"));
  r.latency_median_ms = j.at("median").get<double>();
  r.latency_p95_ms = j.at("p95").get<double>();
  r.setup_s = j.at("setup").get<double>();
  r.frames = j.at("frames").get<int>();
  r.settings = j.at("settings").get<std::string>();
  return r;
}
json images_json(const std::vector<Eigen::VectorXd>& images) {
  json out = json::array();
  for (const auto& im : images) out.push_back(std::vector<float>(im.data(), im.data() + im.size()));
  return out;
}
std::vector<Eigen::VectorXd> images_from(const json& j) {
  std::vector<Eigen::VectorXd> out;
  for (const auto& im : j) {
    const auto v = im.get<std::vector<float>>();
    out.push_back(Eigen::Map<const Eigen::VectorXf>(v.data(), static_cast<Eigen::Index>(v.size()))
                      .cast<double>());
  }
  return out;
}

// Quality on every frame (reconstruct_all), latency on the first `timed` one at a time, after
// a few untimed calls: the first single-frame calls pay one-off costs (LibTorch sets up its
// kernels and memory pools for the batch-of-one shape) that a sensor streaming frames pays once.
ResultRow evaluate(const Reconstructor& method, const SampleMatrix& frames,
                   const SampleMatrix& labels, const PixelGrid& grid, int timed,
                   SampleMatrix* images_out) {
  ResultRow row;
  const SampleMatrix images = method.reconstruct_all(frames);
  const int n = std::min<int>(timed, static_cast<int>(frames.rows()));
  for (int i = 0; i < std::min(n, 3); ++i) method.reconstruct(frames.row(i).transpose());
  std::vector<double> ms;
  for (int i = 0; i < n; ++i) {
    const Eigen::VectorXd frame = frames.row(i).transpose();
    const auto t0 = std::chrono::steady_clock::now();
    const Eigen::VectorXd image = method.reconstruct(frame);
    ms.push_back(seconds_since(t0) * 1e3);
    if (!image.allFinite()) throw std::runtime_error(method.name() + ": non-finite image");
  }
  row.latency_median_ms = percentile(ms, 0.5);
  row.latency_p95_ms = percentile(ms, 0.95);
  if (labels.rows() == frames.rows() && labels.cols() > 0) {
    const ScoreSummary s = score_images(images, labels, grid);
    row.cc = s.mean.cc, row.re = s.mean.re, row.ssim = s.mean.ssim, row.mse = s.mean.mse;
    row.cc_std = s.std.cc, row.re_std = s.std.re;
    row.frames = static_cast<int>(frames.rows());
  } else {
    row.cc = row.re = row.ssim = row.mse = row.cc_std = row.re_std = NAN;
  }
  row.settings = method.settings();
  if (images_out) *images_out = images;
  return row;
}

std::string quality(const ResultRow& row) {
  return row.frames > 0 ? fmt::format("CC {:.3f}, RE {:.3f}", row.cc, row.re) : "no labels";
}

// The calibration of evaluated frames to the simulated preset, for the log and the report.
std::string describe(const ReferenceCalibration& c) {
  return std::isnan(c.fit)
             ? "none (no reference frame: the frames are taken as differences in the preset's "
               "units)"
             : fmt::format(
                   "frames × {:.6g}, the least-squares fit of the data's reference frame "
                   "to the simulated preset's (cosine {:.6f})",
                   c.scale, c.fit);
}

std::vector<Eigen::VectorXd> first_images(const SampleMatrix& images, int count) {
  std::vector<Eigen::VectorXd> out;
  for (Eigen::Index i = 0; i < std::min<Eigen::Index>(count, images.rows()); ++i)
    out.push_back(images.row(i).transpose());
  return out;
}

}  // namespace

RunResults run_benchmark(const RunConfig& config) {
  const auto t_start = std::chrono::steady_clock::now();
  const fs::path out(config.out);
  if (fs::exists(out) && !fs::is_directory(out))
    throw InputError(config.out, "", "is a file; --out takes a folder");
  std::error_code error;
  fs::create_directories(out / "models", error);
  if (error) throw InputError(config.out, "", "cannot create the folder: " + error.message());
  const Stages stages(out / "stages", config.resume);
  auto say = [&](const std::string& line) {
    if (!config.quiet) fmt::print("{}\n", line), std::fflush(stdout);
  };
  set_torch_threads(config.threads);

  // 1. The data: simulated for the preset, or the user's.
  Dataset data, source;  // `data` is evaluated; `source` trains and chooses hyperparameters
  const std::string simulated_path = (out / "data.h5").string();
  auto simulate = [&]() {
    if (config.resume && fs::exists(simulated_path)) {
      Dataset d = read_dataset(simulated_path);
      if (d.preset == config.preset && d.seed == config.seed) {
        say(fmt::format("data: {} samples from {} (resumed)", d.size(), simulated_path));
        return d;
      }
    }
    SimulationOptions s;
    s.preset = config.preset;
    s.seed = config.seed;
    s.density = config.simulation;
    s.electrodes = config.electrodes;
    const auto counts = preset_counts(config.preset);
    int total = 0;
    for (int c : counts.circles) total += c;
    say(fmt::format("data: simulating the {} preset ({} samples, seed {}, {} mesh)", config.preset,
                    total, config.seed, to_string(config.simulation)));
    Progress progress("simulate", total, config.quiet);
    Dataset d = simulate_dataset(s, [&](int done, int) { progress.update(done); });
    write_dataset(simulated_path, d);
    return d;
  };
  bool labelled = true;
  if (config.data.empty()) {
    data = simulate();
  } else {
    if (is_hdf5_file(config.data) && config.reference.empty()) {
      data = read_dataset(config.data);
    } else {
      ImportOptions o;
      o.electrodes = config.electrodes;
      data = import_measurements(config.data, config.reference, o);
    }
    say(fmt::format("data: {} frames from {}{}", data.size(), config.data,
                    data.has_labels() ? "" : " (no labels: images and speed only)"));
  }
  const bool own_training = data.has_labels() && !data.indices(Split::train).empty() &&
                            !data.indices(Split::validation).empty();
  if (own_training) {
    source = data;
  } else {
    labelled = data.has_labels();
    say("training and hyperparameters: the simulated preset (the data have no labelled "
        "train/validation splits)");
    source = simulate();
  }
  std::vector<int> test_rows = data.indices(Split::test);
  if (test_rows.empty() && !data.has_labels())  // measured frames: all of them
    for (int i = 0; i < data.size(); ++i) test_rows.push_back(i);
  if (test_rows.empty()) throw InputError(config.data, "split", "no test frames to evaluate");
  Frames test = rows_of(data, test_rows);
  const Frames validation = rows_of(source, source.indices(Split::validation));
  // The methods are set up for the sensor of the data that tune and train them. When that is the
  // simulated preset, the evaluated frames must match its sensor and are brought to its units.
  const Dataset& sensor = own_training ? data : source;
  ReferenceCalibration calibration;
  if (!own_training) {
    if (data.electrodes != source.electrodes)
      throw InputError(
          config.data, "electrodes",
          fmt::format("{} electrodes, but the preset simulates {}: pass --electrodes {}",
                      data.electrodes, source.electrodes, data.electrodes));
    if (labelled && data.image_size != source.image_size)
      throw InputError(
          config.data, "image_size",
          fmt::format("{}×{} labels, but the preset's images are {}×{}", data.image_size,
                      data.image_size, source.image_size, source.image_size));
    calibration = calibrate_to_model(data.reference, source.reference);
    test.frames *= calibration.scale;
    say("calibration: " + describe(calibration));
    if (calibration.fit < 0.95)
      say("warning: the reference frame fits the model's poorly; check --electrodes and the "
          "measurement order (--order of eitbench import)");
  }
  // Measured frames carry their own noise: they are evaluated as they are.
  const std::vector<double> snrs =
      data.preset == "imported" ? std::vector<double>{INFINITY} : config.snrs;

  // 2. The reconstruction model: the mesh, the Jacobian, the pixel map.
  const auto t_setup = std::chrono::steady_clock::now();
  DiskMeshOptions disk;
  disk.electrodes = sensor.electrodes;
  disk.density = config.mesh;
  disk.radius = sensor.radius;
  disk.electrode_coverage = sensor.electrode_coverage;
  const Mesh mesh = generate_disk_mesh(disk);
  ForwardOptions fo;
  fo.contact_impedance = sensor.contact_impedance;
  fo.current = sensor.current;
  const auto model = std::make_shared<const ForwardModel>(mesh, fo);
  const PixelGrid grid(sensor.image_size, sensor.radius);
  const double background = sensor.background;
  const LinearProblem problem = make_linear_problem(model, background, grid);
  const double problem_s = seconds_since(t_setup);
  say(
      fmt::format("reconstruction mesh: {} triangles; Jacobian and pixel map in {:.2f} s; "
                  "{} test frames, {} validation frames",
                  mesh.num_triangles(), problem_s, test.frames.rows(), validation.frames.rows()));

  // Noisy copies, one seed per SNR (and another for validation).
  std::vector<SampleMatrix> test_at, validation_at;
  for (std::size_t k = 0; k < snrs.size(); ++k) {
    SampleMatrix t = test.frames, v = validation.frames;
    if (std::isfinite(snrs[k])) {
      add_noise(t, snrs[k], config.seed * 1000 + 2 * k + 1);
      add_noise(v, snrs[k], config.seed * 1000 + 2 * k + 2);
    }
    test_at.push_back(t), validation_at.push_back(v);
  }

  RunResults results;
  results.program = program_version();
  std::vector<ImageRow> figure_rows;
  figure_rows.push_back({"truth", first_images(test.labels, config.figure_samples)});
  if (!labelled) figure_rows.clear();
  const ScoreFn score = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
    return correlation(x, y, grid);
  };

  // 3. The model-based methods: hyperparameter by validation CC at each SNR.
  for (const std::string& name : config.methods) {
    json cached;
    if (stages.find("method_" + name, cached)) {
      for (const auto& r : cached.at("rows")) results.rows.push_back(row_from(r));
      figure_rows.push_back({name, images_from(cached.at("images"))});
      say(fmt::format("{}: resumed", name));
      continue;
    }
    json rows = json::array();
    std::vector<Eigen::VectorXd> images;
    for (std::size_t k = 0; k < snrs.size(); ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      MethodOptions mo;
      mo.choose = "validation";
      auto method = make_reconstructor(name, problem, mo);
      // The iterative methods' sweeps cost a solve per frame and candidate: a subset.
      const bool iterative = name == "tv" || name == "gn";
      const Eigen::Index nv =
          iterative ? std::min<Eigen::Index>(config.sweep_frames, validation.frames.rows())
                    : validation.frames.rows();
      method->fit(validation_at[k].topRows(nv), validation.labels.topRows(nv), score);
      const double setup = problem_s + seconds_since(t0);
      SampleMatrix all;
      ResultRow row = evaluate(*method, test_at[k], labelled ? test.labels : SampleMatrix(), grid,
                               config.timed_frames, &all);
      row.method = name, row.snr_db = snrs[k], row.setup_s = setup;
      say(fmt::format("{:>9} at {:>3} dB: {}, {:.3g} ms a frame ({})", name, snr_label(snrs[k]),
                      quality(row), row.latency_median_ms, row.settings));
      if (k == 0) images = first_images(all, config.figure_samples);
      results.rows.push_back(row);
      rows.push_back(row_json(row));
    }
    figure_rows.push_back({name, images});
    stages.save("method_" + name, {{"rows", rows}, {"images", images_json(images)}});
  }

  // 4. The learned reconstructor, trained without and with augmentation.
  const ModelSize size = parse_model_size(config.model, "model");
  NetworkOptions network =
      NetworkOptions::preset(size, static_cast<int>(source.differences.cols()), source.image_size);
  network.radius = source.radius;
  TrainingOptions base;
  base.batch_size = config.batch;
  base.learning_rate = config.learning_rate;
  base.seed = config.seed;
  base.device = resolve_device(config.device, "--device");
  const LabelledFrames source_validation = labelled_frames(source, Split::validation);
  std::vector<std::pair<std::string, std::vector<EpochRecord>>> curves;
  long long parameters = 0;  // of the network, for the report
  for (const std::string& augment : config.augments) {
    const std::string path = (out / "models" / ("dnn_" + augment + ".pt")).string();
    TrainingSummary summary;
    summary.augment = augment;
    std::unique_ptr<LearnedModel> learned;
    if (config.resume && fs::exists(path)) {
      learned = std::make_unique<LearnedModel>(read_model_file(path));
      const json t = json::parse(learned->info().training);
      summary.history = history_from_json(t.at("history").dump(), path);
      summary.best_epoch = t.at("best_epoch").get<int>();
      say(fmt::format("dnn {}: resumed from {}", augment, path));
    } else {
      TrainingOptions o = base;
      o.augment = parse_group(augment, "augment");
      o.epochs = config.epochs;
      TrainingRun run;
      run.out = path;
      run.resume = config.resume && fs::exists(checkpoint_path(path));
      run.quiet = config.quiet;
      run.label = "dnn " + augment;
      run.curves = false;
      say(fmt::format("dnn {}: training the {} model, {} epochs of {} samples", augment,
                      config.model, config.epochs, source.indices(Split::train).size()));
      TrainingResult r = train_and_save(network, o, labelled_frames(source, Split::train),
                                        source_validation, sensor_of(source), run);
      learned = std::make_unique<LearnedModel>(std::move(r.model));
      summary.history = r.history;
      summary.best_epoch = r.best_epoch;
    }
    for (const auto& e : summary.history)
      summary.seconds += e.seconds, summary.samples += e.samples_per_second * e.seconds;
    summary.samples_per_second = summary.seconds > 0 ? summary.samples / summary.seconds : 0;
    if (!summary.history.empty()) summary.steps = summary.history.back().steps;
    curves.emplace_back(augment, summary.history);
    results.training.push_back(summary);
    if (learned->info().electrodes != data.electrodes)
      throw InputError(path, "electrodes", "the model does not fit the data's sensor");
    parameters = learned->parameters();
    const auto method = make_learned_reconstructor(*learned);
    std::vector<Eigen::VectorXd> images;
    for (std::size_t k = 0; k < snrs.size(); ++k) {
      SampleMatrix all;
      ResultRow row = evaluate(*method, test_at[k], labelled ? test.labels : SampleMatrix(), grid,
                               config.timed_frames, &all);
      row.method = "dnn", row.augment = augment, row.snr_db = snrs[k];
      row.setup_s = summary.seconds;
      say(fmt::format("dnn {:>9} at {:>3} dB: {}, {:.3g} ms a frame", augment, snr_label(snrs[k]),
                      quality(row), row.latency_median_ms));
      if (k == 0) images = first_images(all, config.figure_samples);
      results.rows.push_back(row);
    }
    figure_rows.push_back({"dnn " + augment, images});
  }

  // 5. Data efficiency (the paper's Fig. 8): test MSE against the training-set size. By default
  // both budgets are the main runs' (their epochs; their steps on the whole training set), so at
  // the whole set the sweep's models are the main runs' models, and those are reused.
  const int train_count = static_cast<int>(source.indices(Split::train).size());
  const long long main_steps_per_epoch =
      train_count / config.batch + (train_count % config.batch >= 2 ? 1 : 0);
  const int sweep_epochs = config.efficiency_epochs > 0 ? config.efficiency_epochs : config.epochs;
  const long long sweep_steps = config.efficiency_steps > 0
                                    ? config.efficiency_steps
                                    : config.epochs * std::max(1LL, main_steps_per_epoch);
  if (labelled)
    for (const std::string augment : {"none", "d16"})
      for (const std::string budget : {"steps", "epochs"})
        for (int n : config.efficiency_sizes) {
          if (n > train_count) continue;
          EfficiencyPoint p;
          p.augment = augment, p.budget = budget, p.train_size = n;
          const bool main_budget = budget == "steps"
                                       ? sweep_steps == config.epochs * main_steps_per_epoch
                                       : sweep_epochs == config.epochs;
          const ResultRow* main_row = nullptr;
          for (const auto& row : results.rows)
            if (row.method == "dnn" && row.augment == augment && std::isinf(row.snr_db))
              main_row = &row;
          if (n == train_count && main_budget && main_row) {  // the main run's model
            for (const auto& t : results.training)
              if (t.augment == augment)
                p.steps = t.steps, p.epochs = static_cast<int>(t.history.size());
            p.test_mse = main_row->mse, p.cc = main_row->cc, p.re = main_row->re;
            results.efficiency.push_back(p);
            continue;
          }
          const std::string name = fmt::format("efficiency_{}_{}_{}", augment, budget, n);
          json cached;
          if (stages.find(name, cached)) {
            p.steps = cached.at("steps").get<long long>();
            p.epochs = cached.at("epochs").get<int>();
            p.test_mse = cached.at("test_mse").get<double>();
            p.cc = cached.at("cc").get<double>();
            p.re = cached.at("re").get<double>();
            results.efficiency.push_back(p);
            continue;
          }
          TrainingOptions o = base;
          o.augment = parse_group(augment, "augment");
          if (budget == "steps")
            o.steps = sweep_steps;
          else
            o.epochs = sweep_epochs;
          TrainingRun run;
          run.out = (out / "models" / (name + ".pt")).string();
          run.resume = config.resume && fs::exists(checkpoint_path(run.out));
          run.quiet = config.quiet;
          run.label = fmt::format("sweep {} {} n={}", augment, budget, n);
          run.curves = false;
          TrainingResult r = train_and_save(network, o, labelled_frames(source, Split::train, n),
                                            source_validation, sensor_of(source), run);
          const auto method = make_learned_reconstructor(r.model);
          const ResultRow row = evaluate(*method, test.frames, test.labels, grid, 0, nullptr);
          p.steps = r.history.back().steps;
          p.epochs = static_cast<int>(r.history.size());
          p.test_mse = row.mse, p.cc = row.cc, p.re = row.re;
          say(
              fmt::format("data efficiency: {} at equal {}, n={}: {} steps, test MSE {:.4g}, "
                          "CC {:.3f}",
                          augment, budget, n, p.steps, p.test_mse, p.cc));
          results.efficiency.push_back(p);
          stages.save(name, {{"steps", p.steps},
                             {"epochs", p.epochs},
                             {"test_mse", p.test_mse},
                             {"cc", p.cc},
                             {"re", p.re}});
        }

  // 6. The files.
  const double total_s = seconds_since(t_start);
  results.machine = describe_machine();
  auto& c = results.configuration;
  c["preset"] = config.preset;
  c["seed"] = std::to_string(config.seed);
  c["data"] = config.data.empty() ? simulated_path : config.data;
  c["data_provenance"] = data.simulation_mesh + " (" + data.preset + ", " + data.program + ")";
  c["test_frames"] = std::to_string(test.frames.rows());
  c["training_samples"] = std::to_string(train_count);
  c["validation_frames"] = std::to_string(validation.frames.rows());
  c["reconstruction_mesh"] = fmt::format("disk L={} {} ({} triangles)", data.electrodes,
                                         to_string(config.mesh), mesh.num_triangles());
  c["background"] = fmt::format("{:g}", background);
  if (!own_training) c["calibration"] = describe(calibration);
  c["snrs_db"] = [&] {
    std::string s;
    for (double v : snrs) s += (s.empty() ? "" : " ") + snr_label(v);
    return s;
  }();
  c["model"] = fmt::format("{} ({} parameters, {:.1f} MFLOP a frame)", config.model, parameters,
                           forward_flops(network) / 1e6);
  c["training"] =
      fmt::format("{} epochs, batch {}, Adam lr {:g}, on-the-fly augmentation, device {}",
                  config.epochs, config.batch, config.learning_rate, base.device);
  c["efficiency"] =
      fmt::format("sizes up to {}, {} steps or {} epochs",
                  config.efficiency_sizes.empty() ? 0 : config.efficiency_sizes.back(),
                  config.efficiency_steps, config.efficiency_epochs);
  c["hyperparameters"] =
      fmt::format("validation CC at each SNR ({} validation frames; tv and gn sweep {})",
                  validation.frames.rows(), config.sweep_frames);
  c["latency"] = fmt::format("the first {} test frames one at a time, wall clock, {} threads",
                             config.timed_frames, config.threads);
  c["total_seconds"] = fmt::format("{:.1f}", total_s);
  results.recommendation = recommend(results.rows);

  write_results_json((out / "results.json").string(), results);
  write_results_csv((out / "results.csv").string(), results.rows);
  draw_image_grid_png(figure_rows, grid.mask(),
                      labelled ? "test samples: truth, then each method (noise-free)"
                               : "measured frames: each method",
                      (out / "reconstructions.png").string());
  write_loss_curves((out / "loss_curves.csv").string(), (out / "loss_curves.png").string(), curves);
  if (!results.efficiency.empty())
    draw_efficiency_png(results.efficiency, (out / "data_efficiency.png").string());
  write_report((out / "report.md").string(), results);
  return results;
}

}  // namespace eitbench
