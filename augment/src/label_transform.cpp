#include "eitbench/augment/label_transform.h"

#include <cmath>
#include <stdexcept>

#include "eitbench/jacobian/error.h"

namespace eitbench {

namespace {

// Where each output pixel of the image moved by an element samples the input (the pixel's centre
// moved back by `back`, in the input's column and row coordinates), as a bilinear stencil: four
// neighbours and their weights, 0 for a neighbour off the grid (the image is 0 there) and for a
// masked pixel.
template <typename Back>
ImageSymmetry::Stencil bilinear_stencil(const PixelGrid& grid, Back back) {
  const int n = grid.size();
  const double w = grid.pixel_width();
  ImageSymmetry::Stencil out;
  out.index.assign(4 * static_cast<std::size_t>(n) * n, 0);
  out.weight.assign(out.index.size(), 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const std::size_t at = 4 * (static_cast<std::size_t>(i) * n + j);
      if (!grid.mask()[i * n + j]) continue;
      const Eigen::Vector2d source = back(grid.center(i, j));
      const double col = (source.x() - grid.left()) / w - 0.5,
                   row = (grid.top() - source.y()) / w - 0.5;
      const int c0 = static_cast<int>(std::floor(col)), r0 = static_cast<int>(std::floor(row));
      const double fc = col - c0, fr = row - r0;
      const int dc[4] = {0, 1, 0, 1}, dr[4] = {0, 0, 1, 1};
      const double wt[4] = {(1 - fc) * (1 - fr), fc * (1 - fr), (1 - fc) * fr, fc * fr};
      for (int k = 0; k < 4; ++k) {
        const int c = c0 + dc[k], r = r0 + dr[k];
        if (c < 0 || c >= n || r < 0 || r >= n) continue;
        out.index[at + k] = r * n + c;
        out.weight[at + k] = wt[k];
      }
    }
  return out;
}

}  // namespace

ImageSymmetry::Stencil ImageSymmetry::stencil(const GroupElement& g, int electrodes,
                                              const PixelGrid& grid) {
  const GroupElement inv = inverse(g, electrodes);
  return bilinear_stencil(
      grid, [&](const Eigen::Vector2d& x) { return transform_point(x, inv, electrodes); });
}

ImageSymmetry::ImageSymmetry(int electrodes, const PixelGrid& grid)
    : electrodes_(electrodes), grid_(grid) {
  for (int index = 0; index < 2 * electrodes; ++index)
    stencils_.push_back(stencil({index % electrodes, index >= electrodes}, electrodes, grid));
}

ImageSymmetry::ImageSymmetry(std::shared_ptr<const ShapedSensor> sensor)
    : electrodes_(sensor ? sensor->group.electrodes : 0),
      grid_(sensor ? sensor->grid : PixelGrid()),
      sensor_(std::move(sensor)) {
  if (!sensor_) throw std::invalid_argument("ImageSymmetry: no sensor");
  stencils_.resize(2 * static_cast<std::size_t>(electrodes_));
  for (const SensorSymmetry& s : sensor_->group.elements) {
    const Isometry back = s.map.inverse();
    stencils_[(s.element.mirror ? electrodes_ : 0) + s.element.rotation] =
        bilinear_stencil(grid_, [&](const Eigen::Vector2d& x) { return back(x); });
  }
}

Eigen::Vector2d ImageSymmetry::move(const Eigen::Vector2d& x, const GroupElement& g) const {
  if (!sensor_) return transform_point(x, g, electrodes_);
  const SensorSymmetry* s = sensor_->group.find(g);
  if (!s)
    throw InputError("ImageSymmetry", "element",
                     g.to_string() + " is not a symmetry of this sensor (its group: " +
                         sensor_->group.name() + ")");
  return s->map(x);
}

std::vector<Circle> ImageSymmetry::move(const std::vector<Circle>& circles,
                                        const GroupElement& g) const {
  std::vector<Circle> out = circles;
  for (Circle& c : out) {
    const Eigen::Vector2d p = move(Eigen::Vector2d(c.x, c.y), g);
    c.x = p.x(), c.y = p.y();
  }
  return out;
}

Eigen::VectorXd ImageSymmetry::gather(const Stencil& s, const Eigen::VectorXd& image) {
  if (4 * static_cast<std::size_t>(image.size()) != s.index.size())
    throw InputError("image", "pixels",
                     "has " + std::to_string(image.size()) + " pixels, not the grid's " +
                         std::to_string(s.index.size() / 4));
  Eigen::VectorXd out(image.size());
  for (Eigen::Index p = 0; p < out.size(); ++p) {
    const std::size_t at = 4 * static_cast<std::size_t>(p);
    double v = 0;
    for (int k = 0; k < 4; ++k) v += s.weight[at + k] * image[s.index[at + k]];
    out[p] = v;
  }
  return out;
}

Eigen::VectorXd ImageSymmetry::apply(const GroupElement& g, const Eigen::VectorXd& image) const {
  return gather(stencil(g), image);
}

const ImageSymmetry::Stencil& ImageSymmetry::stencil(const GroupElement& g) const {
  const Stencil& s = stencils_.at((g.mirror ? electrodes_ : 0) + g.rotation);
  if (s.index.empty()) move(Eigen::Vector2d::Zero(), g);  // throws, naming the element
  return s;
}

Eigen::VectorXd moved_label(const Eigen::VectorXd& label, const std::vector<Circle>* circles,
                            double background, const GroupElement& g, const ImageSymmetry& images) {
  if (circles) return circles_image(images.grid(), images.move(*circles, g), background);
  return images.apply(g, label);
}

Eigen::VectorXd transform_image(const Eigen::VectorXd& image, const GroupElement& g, int electrodes,
                                const PixelGrid& grid) {
  return ImageSymmetry::gather(ImageSymmetry::stencil(g, electrodes, grid), image);
}

}  // namespace eitbench
