#pragma once
// Figures people would rather look at than read.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "eitbench/jacobian/mesh.h"

namespace eitbench {

// Whether this build writes PNGs (OpenCV's imgcodecs; EITBENCH_WITH_FIGURES). Without, every
// draw_*_png throws InputError naming the file, and the run and the report leave figures out.
bool can_draw_figures();

// The mesh's triangles, its electrodes in colour with their numbers, and the centre node, as a PNG.
void draw_mesh_png(const Mesh& mesh, const std::string& path, int pixels = 900);

// One curve of a line plot; colour as {blue, green, red} (OpenCV's plots), or by `key` in gnuplot's
// (gnuplot.h: one colour per method across every figure).
struct PlotSeries {
  std::vector<double> x, y;  // x empty: 0, 1, 2, ...
  std::string label;
  std::array<int, 3> colour{200, 90, 20};
  std::string key;                // the series' method ("dnn (d16)"); empty: the label
  bool dashed = false;            // a second line of the same method (training loss, equal steps)
  bool points = false;            // mark each point
  bool only_points = false;       // points and no line (marks on other series: gnuplot only)
  std::vector<double> low, high;  // error bars, one a point (empty: none)
};

// An image of an n x n pixel field (row-major, row 0 at the top) with a colour bar, beside a line
// plot, as one PNG: the mesh's rim and electrodes are drawn over the image when given.
struct SampleFigure {
  std::string title;
  Eigen::VectorXd image;  // n^2 values; NaN or masked pixels drawn white
  Eigen::Array<bool, Eigen::Dynamic, 1> mask;
  double image_min = 0, image_max = 1;
  const Mesh* outline = nullptr;  // drawn in the image's coordinates [-R, R]^2
  double radius = 1.0;
  // Points marked on the image with a ringed cross (a known touch), in its coordinates.
  std::vector<Eigen::Vector2d> marks;
  std::string plot_title, x_label, y_label;
  std::vector<PlotSeries> series;
};
void draw_sample_png(const SampleFigure& figure, const std::string& path);

// A line plot on its own (loss curves, data efficiency), optionally with logarithmic axes.
struct LinePlot {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  bool log_x = false, log_y = false;  // non-positive values are left out on a log axis
  // Labels of x = 0, 1, 2, ... (commits in a history; gnuplot only); empty: the numbers.
  std::vector<std::string> x_tick_labels;
};
void draw_plot_png(const LinePlot& plot, const std::string& path, int width = 900,
                   int height = 560);

// Rows of images side by side with a label on the left (the paper's Fig. 7: a truth row, then one
// row per method). Each image is scaled from min(0, its minimum) to its maximum; pixels outside
// `mask` are white.
struct ImageRow {
  std::string label;
  std::vector<Eigen::VectorXd> images;  // n^2 values each
  // When low < high, every image of the row on that one scale (classes 0 ... 2, a signed range)
  // instead of its own.
  double low = 0, high = 0;
};
void draw_image_grid_png(const std::vector<ImageRow>& rows,
                         const Eigen::Array<bool, Eigen::Dynamic, 1>& mask,
                         const std::string& title, const std::string& path, int cell = 112);

}  // namespace eitbench
