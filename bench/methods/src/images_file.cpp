#include "eitbench/bench/methods/images_file.h"

#include <H5Cpp.h>

#include <cmath>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/hdf5_attributes.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

void write_images_file(const std::string& path, const ImagesFile& c) {
  write_atomically(path, [&](const std::string& temp) {
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
      file.createDataSet("images", H5::PredType::NATIVE_FLOAT, H5::DataSpace(3, dims), props)
          .write(images.data(), H5::PredType::NATIVE_FLOAT);
      const hsize_t count = c.frame_index.size();
      file.createDataSet("frame_index", H5::PredType::NATIVE_INT, H5::DataSpace(1, &count))
          .write(c.frame_index.data(), H5::PredType::NATIVE_INT);
      if (!c.scores.empty()) {
        std::vector<double> table;
        for (const auto& s : c.scores) table.insert(table.end(), {s.cc, s.re, s.mse, s.ssim});
        const hsize_t sdims[2] = {c.scores.size(), 4};
        H5::DataSet set =
            file.createDataSet("scores", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(2, sdims));
        set.write(table.data(), H5::PredType::NATIVE_DOUBLE);
        detail::write_attribute(set, "columns", std::string("cc, re, mse, ssim"));
      }
      for (const auto& [key, value] : c.text) detail::write_attribute(file, key, value);
      for (const auto& [key, value] : c.numbers) detail::write_attribute(file, key, value);
    } catch (const H5::Exception& e) {
      throw InputError(path, "", "HDF5 write failed: " + e.getDetailMsg());
    }
  });
}

}  // namespace eitbench
