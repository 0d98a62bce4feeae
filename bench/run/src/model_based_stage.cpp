// Stages 2 and 3: the reconstruction model, the noisy frames, and each model-based method tuned
// on validation data and scored on the test split.
#include <fmt/core.h>

#include <chrono>
#include <cmath>

#include "eitbench/bench/data/noise.h"
#include "eitbench/bench/data/sensor.h"
#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/bench/methods/evaluate.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/bench/methods/touch_signal.h"
#include "eitbench/bench/support/timing.h"
#include "eitbench/jacobian.h"
#include "stages.h"

namespace eitbench::run {
std::string quality(const ResultRow& row) {
  if (row.frames == 0) return "no labels";
  std::string text = fmt::format("CC {:.3f}, RE {:.3f}", row.cc, row.re);
  const TouchScores& t = row.touch;
  if (t.frames > 0)
    text += fmt::format("; touches: count {:.0f} %, centre {:.3f} R (threshold {:g})",
                        100 * t.count_accuracy, t.centre_error_median, t.threshold);
  return text;
}

Reconstruction set_up_reconstruction(const Context& context, const RunData& data) {
  const Dataset& sensor = data.sensor();
  const auto t0 = std::chrono::steady_clock::now();
  // The disk at the run's density, or a sensor of another shape on its own mesh and grid.
  Reconstruction r{reconstruction_mesh(sensor, context.config.mesh), image_grid(sensor), {}, 0, {}};
  ForwardOptions fo;
  fo.contact_impedance = sensor.contact_impedance;
  fo.current = sensor.current;
  fo.protocol = std::make_shared<const MeasurementProtocol>(measurement_protocol(sensor));
  double background = sensor.background;
  if (!context.config.sensor.empty()) {  // a calibrated sensor replaces the data set's values
    const SensorFile calibrated =
        read_sensor_file(context.config.sensor, sensor.electrodes, "the data have");
    if (apply_fitted_sensor(calibrated, fo)) background = calibrated.background;
  }
  const auto model = std::make_shared<const ForwardModel>(r.mesh, fo);
  r.problem = std::make_shared<const LinearProblem>(make_linear_problem(model, background, r.grid));
  r.setup_s = seconds_since(t0);
  if (scores_touches(data))
    r.test_touches =
        touch_visibility(*model, data.test.circles, data.test.frames, data.data.background);
  context.say(fmt::format(
      "reconstruction mesh: {} triangles; Jacobian and pixel map in {:.2f} s; "
      "{} test frames, {} validation frames",
      r.mesh.num_triangles(), r.setup_s, data.test.frames.rows(), data.validation.frames.rows()));
  return r;
}

NoisyFrames noisy_copies(const RunConfig& config, const RunData& data) {
  NoisyFrames noisy;
  for (std::size_t k = 0; k < data.snrs.size(); ++k) {
    SampleMatrix t = data.test.frames, v = data.validation.frames;
    if (std::isfinite(data.snrs[k])) {
      add_noise(t, data.snrs[k], config.seed * 1000 + 2 * k + 1);
      add_noise(v, data.snrs[k], config.seed * 1000 + 2 * k + 2);
    }
    noisy.test.push_back(t), noisy.validation.push_back(v);
  }
  return noisy;
}

ResultRow evaluate_row(const Reconstructor& method, const SampleMatrix& frames,
                       const SampleMatrix& labels, const PixelGrid& grid, int timed_frames,
                       SampleMatrix* images, std::vector<std::vector<Circle>>* circles) {
  EvaluationOptions options;
  options.timed_frames = timed_frames;
  Evaluation e = evaluate(method, frames, labels, grid, options);
  ResultRow row;
  row.latency_median_ms = e.latency_median_ms;
  row.latency_p95_ms = e.latency_p95_ms;
  if (e.scores.count > 0) {
    row.cc = e.scores.mean.cc, row.re = e.scores.mean.re;
    row.ssim = e.scores.mean.ssim, row.mse = e.scores.mean.mse;
    row.cc_std = e.scores.std.cc, row.re_std = e.scores.std.re;
    row.frames = e.scores.count;
    for (const ImageScores& f : e.each) row.frame_cc.push_back(f.cc), row.frame_re.push_back(f.re);
  } else {
    row.cc = row.re = row.ssim = row.mse = row.cc_std = row.re_std = NAN;
  }
  row.settings = e.settings;
  if (images) *images = std::move(e.images);
  if (circles) *circles = std::move(e.circles);
  return row;
}

std::vector<Eigen::VectorXd> first_images(const SampleMatrix& images, int count) {
  std::vector<Eigen::VectorXd> out;
  for (Eigen::Index i = 0; i < std::min<Eigen::Index>(count, images.rows()); ++i)
    out.push_back(images.row(i).transpose());
  return out;
}

void fit_on_validation(Reconstructor& method, const std::string& name, const RunConfig& config,
                       const SampleMatrix& frames, const SampleMatrix& labels,
                       const PixelGrid& grid) {
  const Eigen::Index n = find_method(name).sweep_on_subset
                             ? std::min<Eigen::Index>(config.sweep_frames, frames.rows())
                             : frames.rows();
  method.fit(frames.topRows(n), labels.topRows(n),
             [&grid](const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
               return correlation(x, y, grid);
             });
}

namespace {

MethodResults tune_and_score(const Context& context, const std::string& name, const RunData& data,
                             const Reconstruction& reconstruction, const NoisyFrames& noisy) {
  const RunConfig& config = context.config;
  MethodResults out;
  for (std::size_t k = 0; k < data.snrs.size(); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    MethodOptions mo;
    mo.choose = "validation";
    auto method = make_reconstructor(name, reconstruction.problem, mo);
    fit_on_validation(*method, name, config, noisy.validation[k], data.validation.labels,
                      reconstruction.grid);
    const double setup = reconstruction.setup_s + seconds_since(t0);
    SampleMatrix images;
    std::vector<std::vector<Circle>> circles;
    ResultRow row =
        evaluate_row(*method, noisy.test[k], data.labelled ? data.test.labels : SampleMatrix(),
                     reconstruction.grid, config.timed_frames, &images, &circles);
    row.method = name, row.snr_db = data.snrs[k], row.setup_s = setup;
    // A method that finds circles is scored on them as found; the rest through their images' blobs.
    row.touch = method->finds_circles() ? circle_touch_scores(data, reconstruction, circles)
                                        : touch_scores(context, data, reconstruction, *method,
                                                       noisy.validation[k], images);
    context.say(fmt::format("{:>9} at {:>3} dB: {}, {:.3g} ms a frame ({})", name,
                            snr_label(data.snrs[k]), quality(row), row.latency_median_ms,
                            row.settings));
    if (k == 0) out.images = first_images(images, config.figure_samples);
    out.rows.push_back(row);
  }
  return out;
}

}  // namespace

MethodResults run_model_based(const Context& context, const std::string& name, const RunData& data,
                              const Reconstruction& reconstruction, const NoisyFrames& noisy) {
  const std::string stage = "method_" + name;
  Provenance provenance = data.provenance;
  provenance["method"] = name;
  MethodResults out;
  if (context.cache.find(stage, provenance,
                         [&](const nlohmann::json& j) { out = method_results_from(j); })) {
    context.say(fmt::format("{}: resumed", name));
    return out;
  }
  out = tune_and_score(context, name, data, reconstruction, noisy);
  context.cache.save(stage, provenance, to_json(out));
  return out;
}

}  // namespace eitbench::run
