#include "eitbench/bench/report/run_store.h"

#include <fmt/core.h>

#include <filesystem>
#include <stdexcept>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/numpy.h"
#include "eitbench/bench/report/efficiency.h"
#include "eitbench/bench/report/loss_curves.h"
#include "eitbench/bench/report/press_report.h"
#include "eitbench/bench/report/report.h"
#include "eitbench/bench/report/touch_report.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/input_file.h"
#include "eitbench/jacobian/pixel_grid.h"

namespace eitbench {
namespace fs = std::filesystem;
namespace {

// The labels of reconstructions.npy's rows, from results.json: the truth when the rows were
// scored against labels, then each (method, augmentation) in the order the run produced them.
std::vector<std::string> figure_labels(const RunResults& results) {
  std::vector<std::string> labels;
  if (!results.rows.empty() && results.rows.front().frames > 0) labels.push_back("truth");
  for (const auto& [method, augment] : methods_in_order(results.rows))
    labels.push_back(augment == "-" ? method : method + " " + augment);
  return labels;
}

void draw_reconstructions(const std::string& path, const RunResults& results,
                          const std::string& out) {
  const auto array = detail::read_npy(read_file_bytes(path, 1LL << 30), path, "");
  const std::vector<std::string> labels = figure_labels(results);
  const auto& s = array.shape;
  if (s.size() != 4 || s[2] != s[3] || s[2] == 0 || s[0] != labels.size())
    throw InputError(
        path, "shape",
        fmt::format("expected ({}, samples, n, n) for the rows of results.json", labels.size()));
  const Eigen::Index pixels = static_cast<Eigen::Index>(s[2] * s[3]);
  std::vector<ImageRow> rows;
  for (std::size_t r = 0; r < s[0]; ++r) {
    ImageRow row{labels[r], {}};
    for (std::size_t k = 0; k < s[1]; ++k)
      row.images.push_back(
          Eigen::Map<const Eigen::VectorXd>(array.values.data() + (r * s[1] + k) * pixels, pixels));
    rows.push_back(std::move(row));
  }
  // The disk's mask depends on n only: a pixel is in when its centre is, whatever the radius. A
  // sensor of another shape stores its own.
  const int n = static_cast<int>(s[2]);
  Eigen::Array<bool, Eigen::Dynamic, 1> mask = PixelGrid(n).mask();
  const fs::path mask_file = fs::path(path).parent_path() / "image_mask.npy";
  if (fs::exists(mask_file)) {
    const auto m =
        detail::read_npy(read_file_bytes(mask_file.string(), 1LL << 26), mask_file.string(), "");
    if (m.shape.size() != 2 || m.shape[0] != s[2] || m.shape[1] != s[3])
      throw InputError(mask_file.string(), "shape",
                       fmt::format("expected ({}, {}), the images' size", n, n));
    for (Eigen::Index p = 0; p < mask.size(); ++p) mask[p] = m.values[p] > 0.5;
  }
  const bool labelled = labels.front() == "truth";
  draw_image_grid_png(rows, mask,
                      labelled ? "test samples: truth, then each method (noise-free)"
                               : "measured frames: each method",
                      out);
}

}  // namespace

void write_run_store(const std::string& folder, const RunResults& results,
                     const std::vector<ImageRow>& figure, const PixelGrid& grid) {
  const int image_size = grid.size();
  write_results_json((fs::path(folder) / "results.json").string(), results);
  // The file keeps images only: their labels are results.json's, and must be the figure's.
  const std::vector<std::string> labels = figure_labels(results);
  if (labels.size() != figure.size())
    throw std::logic_error("write_run_store: the figure's rows do not follow results.json's");
  for (std::size_t r = 0; r < figure.size(); ++r)
    if (figure[r].label != labels[r])
      throw std::logic_error("write_run_store: figure row '" + figure[r].label + "' where '" +
                             labels[r] + "' belongs");
  const std::size_t samples = figure.empty() ? 0 : figure.front().images.size();
  const std::size_t pixels = static_cast<std::size_t>(image_size) * image_size;
  std::vector<float> values;
  values.reserve(figure.size() * samples * pixels);
  for (const auto& row : figure) {
    if (row.images.size() != samples)
      throw std::logic_error("write_run_store: rows with different numbers of images");
    for (const auto& im : row.images) {
      if (static_cast<std::size_t>(im.size()) != pixels)
        throw std::logic_error("write_run_store: an image of the wrong size");
      for (Eigen::Index i = 0; i < im.size(); ++i) values.push_back(static_cast<float>(im[i]));
    }
  }
  const std::vector<std::size_t> shape{figure.size(), samples, static_cast<std::size_t>(image_size),
                                       static_cast<std::size_t>(image_size)};
  write_bytes_atomically((fs::path(folder) / "reconstructions.npy").string(),
                         detail::npy_bytes(values, shape));
  const fs::path mask = fs::path(folder) / "image_mask.npy";
  if (grid.is_disk()) {
    std::error_code error;
    fs::remove(mask, error);  // an earlier run's in this folder would mask the disk's images
  } else {
    std::vector<float> inside(grid.mask().size());
    for (Eigen::Index p = 0; p < grid.mask().size(); ++p) inside[p] = grid.mask()[p] ? 1.0f : 0.0f;
    write_bytes_atomically(mask.string(), detail::npy_bytes(inside, {shape[2], shape[3]}));
  }
}

RunResults draw_run_report(const std::string& folder, bool quiet) {
  const fs::path dir(folder);
  require_input_folder(folder);
  RunResults results = read_results_json((dir / "results.json").string());
  // The pick is derived, like the figures: made again by this version's rule, so that a report
  // re-drawn after the rule changed follows it (results.json keeps what the run said).
  results.recommendation = recommend(results.rows, results.training);
  const fs::path images = dir / "reconstructions.npy";
  if (!can_draw_figures()) {
    if (!quiet)
      fmt::print("this build draws no figures: `eitbench report {}` on one that does\n", folder);
  } else if (fs::exists(images)) {
    draw_reconstructions(images.string(), results, (dir / "reconstructions.png").string());
  } else if (!quiet) {
    fmt::print("{}: not found; reconstructions.png is left as it is\n", images.string());
  }
  write_results_csv((dir / "results.csv").string(), results.rows);
  std::vector<std::pair<std::string, std::vector<TrainingRecord>>> curves;
  for (const auto& t : results.training) curves.emplace_back(t.augment, t.history);
  // The line plots are gnuplot's: without it their data and scripts are written all the same.
  bool drawn = write_loss_curves((dir / "loss_curves.csv").string(),
                                 (dir / "loss_curves.png").string(), curves);
  if (!results.efficiency.empty())
    drawn = draw_efficiency_figures(results.efficiency, dir.string()) && drawn;
  if (has_touch_scores(results.rows))
    drawn = draw_touch_figure(results.rows, headline_snr(results.rows),
                              (dir / "touch_centre_errors.png").string()) &&
            drawn;
  if (!results.measured.empty())
    drawn = draw_press_figure(results, (dir / "press_finetune.png").string()) && drawn;
  if (!drawn && !quiet)
    fmt::print(
        "gnuplot is not installed: the line plots are left as data (.dat) and scripts (.gp) in {}; "
        "`apt-get install gnuplot-nox`, then `eitbench report {}` (or `gnuplot NAME.gp` there)\n",
        folder, folder);
  write_report((dir / "report.md").string(), results);
  return results;
}

}  // namespace eitbench
