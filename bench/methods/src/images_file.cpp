#include "eitbench/bench/methods/images_file.h"

#include <H5Cpp.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/child_write.h"
#include "eitbench/bench/io/hdf5_attributes.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

constexpr hsize_t kMaxCircles = 4;  // the data set's /circles holds up to 4 a frame

// /circles and /circle_count as the data set has them; a method that found more than 4 keeps
// its first 4 there (the count says how many it found).
void write_circles(H5::H5File& file, const std::vector<std::vector<Circle>>& circles) {
  const hsize_t n = circles.size();
  std::vector<double> table(n * kMaxCircles * 4, NAN);
  std::vector<int> count(n);
  for (hsize_t i = 0; i < n; ++i) {
    count[i] = static_cast<int>(circles[i].size());
    for (hsize_t k = 0; k < std::min<hsize_t>(kMaxCircles, circles[i].size()); ++k) {
      const Circle& c = circles[i][k];
      std::copy_n(std::array<double, 4>{c.x, c.y, c.r, c.conductivity}.begin(), 4,
                  table.begin() + static_cast<std::ptrdiff_t>((i * kMaxCircles + k) * 4));
    }
  }
  const hsize_t dims[3] = {n, kMaxCircles, 4};
  detail::write_closed(
      file.createDataSet("circles", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(3, dims)),
      table.data(), H5::PredType::NATIVE_DOUBLE);
  detail::write_closed(
      file.createDataSet("circle_count", H5::PredType::NATIVE_INT, H5::DataSpace(1, &n)),
      count.data(), H5::PredType::NATIVE_INT);
}

}  // namespace

void write_images_file(const std::string& path, const ImagesFile& c) {
  // libhdf5 does not recover from a failed write: a child writes the file (child_write.h).
  write_atomically(path, [&](const std::string& temp) {
    detail::write_in_child(path, [&] {
      try {
        H5::Exception::dontPrint();
        H5::H5File file(temp, H5F_ACC_TRUNC);
        const hsize_t n = static_cast<hsize_t>(c.images.rows());
        const hsize_t side =
            static_cast<hsize_t>(std::lround(std::sqrt(static_cast<double>(c.images.cols()))));
        const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> images =
            c.images.cast<float>();
        const hsize_t dims[3] = {n, side, side};
        H5::DSetCreatPropList props;
        if (n > 0) {
          const hsize_t chunk[3] = {std::min<hsize_t>(n, 64), side, side};
          props.setChunk(3, chunk);
          props.setDeflate(1);
        }
        detail::write_closed(
            file.createDataSet("images", H5::PredType::NATIVE_FLOAT, H5::DataSpace(3, dims), props),
            images.data(), H5::PredType::NATIVE_FLOAT);
        const hsize_t count = c.frame_index.size();
        detail::write_closed(
            file.createDataSet("frame_index", H5::PredType::NATIVE_INT, H5::DataSpace(1, &count)),
            c.frame_index.data(), H5::PredType::NATIVE_INT);
        if (!c.scores.empty()) {
          std::vector<double> table;
          for (const auto& s : c.scores) table.insert(table.end(), {s.cc, s.re, s.mse, s.ssim});
          const hsize_t sdims[2] = {c.scores.size(), 4};
          H5::DataSet set =
              file.createDataSet("scores", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(2, sdims));
          set.write(table.data(), H5::PredType::NATIVE_DOUBLE);
          detail::write_attribute(set, "columns", std::string("cc, re, mse, ssim"));
          set.close();
        }
        if (!c.circles.empty()) write_circles(file, c.circles);
        for (const auto& [key, value] : c.text) detail::write_attribute(file, key, value);
        for (const auto& [key, value] : c.numbers) detail::write_attribute(file, key, value);
        file.close();  // here, where a failure throws, not in the destructor
      } catch (const H5::Exception& e) {
        throw InputError(path, "", "HDF5 write failed: " + e.getDetailMsg());
      }
    });
  });
}

}  // namespace eitbench
