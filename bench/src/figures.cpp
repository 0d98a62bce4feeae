#include "eitbench/bench/figures.h"

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "eitbench/bench/io.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

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
  write_atomically(path, [&](const std::string& temp) {
    if (!cv::imwrite(temp, image)) throw InputError(path, "", "cannot write the PNG");
  });
}

}  // namespace eitbench
