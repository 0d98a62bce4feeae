#include "eitbench/augment/label_transform.h"

#include <cmath>

#include "eitbench/jacobian/error.h"

namespace eitbench {

// Where each output pixel of the image moved by g samples the input (the pixel's centre moved back
// by g, in the input's column and row coordinates), as a bilinear stencil: four neighbours and
// their weights, 0 for a neighbour off the grid (the image is 0 there) and for a pixel outside the
// disk.
ImageSymmetry::Stencil ImageSymmetry::stencil(const GroupElement& g, int electrodes,
                                              const PixelGrid& grid) {
  const int n = grid.size();
  const double w = grid.pixel_width(), R = grid.radius();
  const GroupElement inv = inverse(g, electrodes);
  Stencil out;
  out.index.assign(4 * static_cast<std::size_t>(n) * n, 0);
  out.weight.assign(out.index.size(), 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const std::size_t at = 4 * (static_cast<std::size_t>(i) * n + j);
      if (!grid.mask()[i * n + j]) continue;
      const Eigen::Vector2d source = transform_point(grid.center(i, j), inv, electrodes);
      const double col = (source.x() + R) / w - 0.5, row = (R - source.y()) / w - 0.5;
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

ImageSymmetry::ImageSymmetry(int electrodes, const PixelGrid& grid)
    : electrodes_(electrodes), grid_(grid) {
  for (int index = 0; index < 2 * electrodes; ++index)
    stencils_.push_back(stencil({index % electrodes, index >= electrodes}, electrodes, grid));
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
  return stencils_[(g.mirror ? electrodes_ : 0) + g.rotation];
}

Eigen::VectorXd moved_label(const Eigen::VectorXd& label, const std::vector<Circle>* circles,
                            double background, const GroupElement& g, int electrodes,
                            const ImageSymmetry& images) {
  if (circles)
    return circles_image(images.grid(), transform_circles(*circles, g, electrodes), background);
  return images.apply(g, label);
}

Eigen::VectorXd transform_image(const Eigen::VectorXd& image, const GroupElement& g, int electrodes,
                                const PixelGrid& grid) {
  return ImageSymmetry::gather(ImageSymmetry::stencil(g, electrodes, grid), image);
}

}  // namespace eitbench
