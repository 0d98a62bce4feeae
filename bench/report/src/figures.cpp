#include "eitbench/bench/report/figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#ifdef EITBENCH_HAVE_FIGURES
#include <opencv2/imgcodecs.hpp>
#endif
#include <opencv2/imgproc.hpp>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

namespace {

// Every figure leaves through here: written atomically, or refused by a build without imgcodecs.
void write_png(const cv::Mat& canvas, const std::string& path) {
#ifdef EITBENCH_HAVE_FIGURES
  write_atomically(path, [&](const std::string& temp) {
    if (!cv::imwrite(temp, canvas)) throw InputError(path, "", "cannot write the PNG");
  });
#else
  (void)canvas;
  throw InputError(path, "",
                   "this build writes no PNG figures (EITBENCH_WITH_FIGURES=OFF): `eitbench "
                   "report DIR` on a build with them draws a run's figures from its results");
#endif
}

}  // namespace

bool can_draw_figures() {
#ifdef EITBENCH_HAVE_FIGURES
  return true;
#else
  return false;
#endif
}

void draw_mesh_png(const Mesh& mesh, const std::string& path, int pixels) {
  const Eigen::Vector2d lo = mesh.nodes.colwise().minCoeff(), hi = mesh.nodes.colwise().maxCoeff();
  const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  const double margin = 0.07 * pixels;
  const double scale = (pixels - 2 * margin) / extent;
  const Eigen::Vector2d mid = 0.5 * (lo + hi);
  auto at = [&](int node) {
    return cv::Point2d(pixels / 2.0 + (mesh.nodes(node, 0) - mid.x()) * scale,
                       pixels / 2.0 - (mesh.nodes(node, 1) - mid.y()) * scale);  // y up
  };
  cv::Mat image(pixels, pixels, CV_8UC3, cv::Scalar(255, 255, 255));
  const int shift = 4;  // sub-pixel precision for cv::line
  auto fixed = [&](cv::Point2d p) {
    return cv::Point(std::lround(p.x * (1 << shift)), std::lround(p.y * (1 << shift)));
  };
  for (int t = 0; t < mesh.num_triangles(); ++t)
    for (int k = 0; k < 3; ++k)
      cv::line(image, fixed(at(mesh.triangles(t, k))), fixed(at(mesh.triangles(t, (k + 1) % 3))),
               cv::Scalar(150, 150, 150), 1, cv::LINE_AA, shift);
  for (int e = 0; e < mesh.num_electrodes(); ++e) {
    const Electrode& el = mesh.electrodes[e];
    const cv::Scalar colour = e == 0 ? cv::Scalar(30, 30, 220) : cv::Scalar(200, 90, 20);  // BGR
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    int count = 0;
    if (el.is_point()) {
      cv::circle(image, at(el.point_node), 6, colour, cv::FILLED, cv::LINE_AA);
      centre = mesh.nodes.row(el.point_node);
      count = 1;
    }
    for (const auto& s : el.segments) {
      cv::line(image, fixed(at(s[0])), fixed(at(s[1])), colour, 5, cv::LINE_AA, shift);
      centre += (mesh.nodes.row(s[0]) + mesh.nodes.row(s[1])).transpose() / 2;
      ++count;
    }
    centre /= count;
    const Eigen::Vector2d out = mid + (centre - mid) * (1 + 0.45 * margin / (0.5 * extent * scale));
    const std::string label = std::to_string(e);
    const cv::Point2d p(pixels / 2.0 + (out.x() - mid.x()) * scale,
                        pixels / 2.0 - (out.y() - mid.y()) * scale);
    cv::putText(image, label,
                cv::Point(std::lround(p.x - 7.0 * label.size()), std::lround(p.y + 7)),
                cv::FONT_HERSHEY_SIMPLEX, 0.6, colour, 2, cv::LINE_AA);
  }
  write_png(image, path);
}

}  // namespace eitbench

namespace eitbench {
namespace {

const cv::Scalar kInk(40, 40, 40), kGrid(225, 225, 225);

std::string short_number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

void put_text(cv::Mat& img, const std::string& text, cv::Point at, double scale = 0.5,
              cv::Scalar colour = kInk) {
  cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv::LINE_AA);
}

// The line plot inside `box`, with axes, ticks at the ends and a legend. On a log axis the
// values are plotted as log10 and labelled back in the data's units.
void draw_plot(cv::Mat& img, cv::Rect box, const LinePlot& f) {
  auto tx = [&](double x) { return f.log_x ? (x > 0 ? std::log10(x) : NAN) : x; };
  auto ty = [&](double y) { return f.log_y ? (y > 0 ? std::log10(y) : NAN) : y; };
  auto back = [](bool log, double v) { return log ? std::pow(10.0, v) : v; };
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const auto& s : f.series)
    for (std::size_t i = 0; i < s.y.size(); ++i) {
      const double x = tx(s.x.empty() ? double(i) : s.x[i]), y = ty(s.y[i]);
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  if (!std::isfinite(x0)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;  // nothing to draw: empty axes
  if (!(x1 > x0)) x1 = x0 + 1;
  if (!(y1 > y0)) y1 = y0 + 1;
  const double pad = 0.05 * (y1 - y0);
  y0 -= pad, y1 += pad;
  const cv::Rect area(box.x + 70, box.y + 30, box.width - 90, box.height - 80);
  auto px = [&](double x, double y) {
    return cv::Point2d(area.x + (x - x0) / (x1 - x0) * area.width,
                       area.y + area.height - (y - y0) / (y1 - y0) * area.height);
  };
  for (int k = 0; k <= 4; ++k) {  // horizontal grid with labels
    const double y = y0 + (y1 - y0) * k / 4;
    cv::line(img, px(x0, y), px(x1, y), kGrid, 1);
    put_text(img, short_number(back(f.log_y, y)),
             cv::Point(box.x + 5, static_cast<int>(px(x0, y).y) + 5), 0.42);
  }
  if (!f.log_y && y0 < 0 && y1 > 0)
    cv::line(img, px(x0, 0), px(x1, 0), cv::Scalar(160, 160, 160), 1);
  cv::rectangle(img, area, kInk, 1);
  put_text(img, short_number(back(f.log_x, x0)), cv::Point(area.x - 5, area.y + area.height + 18),
           0.42);
  put_text(img, short_number(back(f.log_x, x1)),
           cv::Point(area.x + area.width - 20, area.y + area.height + 18), 0.42);
  put_text(img, f.x_label + (f.log_x ? " (log)" : ""),
           cv::Point(area.x + area.width / 2 - 60, area.y + area.height + 38), 0.48);
  put_text(img, f.y_label + (f.log_y ? " (log)" : ""), cv::Point(box.x + 5, box.y + 18), 0.48);
  put_text(img, f.title,
           cv::Point(area.x + 10 + 8 * static_cast<int>(f.y_label.size()), box.y + 18), 0.55);
  int legend_y = area.y + 18;
  for (const auto& s : f.series) {
    const cv::Scalar colour(s.colour[0], s.colour[1], s.colour[2]);
    bool have_last = false;
    cv::Point2d last;
    for (std::size_t i = 0; i < s.y.size(); ++i) {
      const double x = tx(s.x.empty() ? double(i) : s.x[i]), y = ty(s.y[i]);
      if (!std::isfinite(x) || !std::isfinite(y)) {
        have_last = false;
        continue;
      }
      const cv::Point2d p = px(x, y);
      if (have_last) cv::line(img, last, p, colour, 2, cv::LINE_AA);
      if (s.y.size() < 30) cv::circle(img, p, 3, colour, cv::FILLED, cv::LINE_AA);
      last = p, have_last = true;
    }
    if (!s.label.empty()) {
      cv::line(img, cv::Point(area.x + area.width - 190, legend_y - 4),
               cv::Point(area.x + area.width - 165, legend_y - 4), colour, 2);
      put_text(img, s.label, cv::Point(area.x + area.width - 158, legend_y), 0.45);
      legend_y += 18;
    }
  }
}

}  // namespace

void draw_sample_png(const SampleFigure& f, const std::string& path) {
  const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(f.image.size()))));
  const int cell = std::max(1, 512 / std::max(1, n)), side = n * cell;
  cv::Mat canvas(side + 90, side + 660, CV_8UC3, cv::Scalar(255, 255, 255));
  // The image through a colour map, masked pixels white.
  cv::Mat grey(n, n, CV_8U);
  const double span = f.image_max > f.image_min ? f.image_max - f.image_min : 1.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double v = (f.image[i * n + j] - f.image_min) / span;
      grey.at<unsigned char>(i, j) = static_cast<unsigned char>(
          std::lround(255 * std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 1.0)));
    }
  cv::Mat colour, big;
  cv::applyColorMap(grey, colour, cv::COLORMAP_VIRIDIS);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if ((f.mask.size() == n * n && !f.mask[i * n + j]) || !std::isfinite(f.image[i * n + j]))
        colour.at<cv::Vec3b>(i, j) = cv::Vec3b(255, 255, 255);
  cv::resize(colour, big, cv::Size(side, side), 0, 0, cv::INTER_NEAREST);
  const cv::Point origin(20, 50);
  big.copyTo(canvas(cv::Rect(origin.x, origin.y, side, side)));
  put_text(canvas, f.title, cv::Point(20, 30), 0.6);
  if (f.outline) {  // the rim and the electrodes of the mesh
    auto at = [&](int node) {
      return cv::Point(
          origin.x + static_cast<int>(std::lround((f.outline->nodes(node, 0) + f.radius) /
                                                  (2 * f.radius) * side)),
          origin.y + static_cast<int>(std::lround((f.radius - f.outline->nodes(node, 1)) /
                                                  (2 * f.radius) * side)));
    };
    std::map<std::pair<int, int>, int> edges;
    for (int t = 0; t < f.outline->num_triangles(); ++t)
      for (int k = 0; k < 3; ++k) {
        const int a = f.outline->triangles(t, k), b = f.outline->triangles(t, (k + 1) % 3);
        ++edges[{std::min(a, b), std::max(a, b)}];
      }
    for (const auto& [e, count] : edges)
      if (count == 1) cv::line(canvas, at(e.first), at(e.second), kInk, 1, cv::LINE_AA);
    for (int e = 0; e < f.outline->num_electrodes(); ++e) {
      const Electrode& el = f.outline->electrodes[e];
      const cv::Scalar c = e == 0 ? cv::Scalar(30, 30, 220) : cv::Scalar(30, 140, 255);
      if (el.is_point()) cv::circle(canvas, at(el.point_node), 5, c, cv::FILLED);
      for (const auto& s : el.segments) cv::line(canvas, at(s[0]), at(s[1]), c, 4, cv::LINE_AA);
    }
  }
  for (const Eigen::Vector2d& m : f.marks) {  // white under red, visible on any colour
    const cv::Point p(
        origin.x + static_cast<int>(std::lround((m.x() + f.radius) / (2 * f.radius) * side)),
        origin.y + static_cast<int>(std::lround((f.radius - m.y()) / (2 * f.radius) * side)));
    for (const auto& [colour, width] :
         {std::pair{cv::Scalar(255, 255, 255), 5}, std::pair{cv::Scalar(40, 40, 230), 2}}) {
      cv::circle(canvas, p, 11, colour, width, cv::LINE_AA);
      cv::drawMarker(canvas, p, colour, cv::MARKER_CROSS, 30, width, cv::LINE_AA);
    }
  }
  // Colour bar.
  const cv::Rect bar(origin.x + side + 12, origin.y, 16, side);
  for (int y = 0; y < side; ++y) {
    cv::Mat one(1, 1, CV_8U, cv::Scalar(255 - 255 * y / std::max(1, side - 1))), c;
    cv::applyColorMap(one, c, cv::COLORMAP_VIRIDIS);
    cv::line(canvas, cv::Point(bar.x, bar.y + y), cv::Point(bar.x + bar.width, bar.y + y),
             cv::Scalar(c.at<cv::Vec3b>(0, 0)), 1);
  }
  put_text(canvas, short_number(f.image_max), cv::Point(bar.x + 20, bar.y + 10), 0.42);
  put_text(canvas, short_number(f.image_min), cv::Point(bar.x + 20, bar.y + side), 0.42);
  LinePlot plot;
  plot.title = f.plot_title, plot.x_label = f.x_label, plot.y_label = f.y_label;
  plot.series = f.series;
  draw_plot(canvas, cv::Rect(origin.x + side + 70, origin.y - 20, 560, side + 40), plot);
  write_png(canvas, path);
}

void draw_plot_png(const LinePlot& plot, const std::string& path, int width, int height) {
  cv::Mat canvas(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  draw_plot(canvas, cv::Rect(10, 10, width - 20, height - 20), plot);
  write_png(canvas, path);
}

void draw_image_grid_png(const std::vector<ImageRow>& rows,
                         const Eigen::Array<bool, Eigen::Dynamic, 1>& mask,
                         const std::string& title, const std::string& path, int cell) {
  std::size_t columns = 0;
  for (const auto& r : rows) columns = std::max(columns, r.images.size());
  const int label_width = 190, gap = 4, top = 40;
  const int width = label_width + static_cast<int>(columns) * (cell + gap) + 10;
  const int height = top + static_cast<int>(rows.size()) * (cell + gap) + 10;
  cv::Mat canvas(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  put_text(canvas, title, cv::Point(10, 26), 0.6);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const int y = top + static_cast<int>(r) * (cell + gap);
    put_text(canvas, rows[r].label, cv::Point(10, y + cell / 2 + 5), 0.5);
    for (std::size_t c = 0; c < rows[r].images.size(); ++c) {
      const Eigen::VectorXd& image = rows[r].images[c];
      const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(image.size()))));
      if (n * n != image.size() || n == 0) continue;
      const bool fixed = rows[r].low < rows[r].high;
      const double lo = fixed ? rows[r].low : std::min(0.0, image.minCoeff());
      const double hi = fixed ? rows[r].high : image.maxCoeff();
      const double span = hi > lo ? hi - lo : 1.0;
      cv::Mat grey(n, n, CV_8U), colour, big;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const double v = (image[i * n + j] - lo) / span;
          grey.at<unsigned char>(i, j) = static_cast<unsigned char>(
              std::lround(255 * std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 1.0)));
        }
      cv::applyColorMap(grey, colour, cv::COLORMAP_VIRIDIS);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          if (mask.size() == n * n && !mask[i * n + j])
            colour.at<cv::Vec3b>(i, j) = cv::Vec3b(255, 255, 255);
      cv::resize(colour, big, cv::Size(cell, cell), 0, 0, cv::INTER_NEAREST);
      big.copyTo(canvas(cv::Rect(label_width + static_cast<int>(c) * (cell + gap), y, cell, cell)));
    }
  }
  write_png(canvas, path);
}

}  // namespace eitbench
