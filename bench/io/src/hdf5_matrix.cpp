#include <H5Cpp.h>

#include <cmath>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/child_write.h"
#include "eitbench/bench/io/hdf5_attributes.h"
#include "eitbench/bench/io/hdf5_matrix.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

void write_hdf5_matrix(const std::string& path, const Hdf5Matrix& c) {
  // libhdf5 does not recover from a failed write: a child writes the file (child_write.h).
  write_atomically(path, [&](const std::string& temp) {
    detail::write_in_child(path, [&] {
      try {
        H5::Exception::dontPrint();
        H5::H5File file(temp, H5F_ACC_TRUNC);
        const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows =
            *c.matrix;
        const hsize_t dims[2] = {static_cast<hsize_t>(rows.rows()),
                                 static_cast<hsize_t>(rows.cols())};
        H5::DataSpace space(2, dims);
        H5::DSetCreatPropList props;
        if (dims[0] > 0 && dims[1] > 0) {
          const hsize_t chunk[2] = {std::min<hsize_t>(dims[0], 64),
                                    std::min<hsize_t>(dims[1], 4096)};
          props.setChunk(2, chunk);
          props.setDeflate(4);
        }
        H5::DataSet set = file.createDataSet(c.name, H5::PredType::NATIVE_DOUBLE, space, props);
        set.write(rows.data(), H5::PredType::NATIVE_DOUBLE);
        const H5::DataSpace scalar(H5S_SCALAR);
        for (const auto& [key, value] : c.text_attributes) {
          const H5::StrType type(H5::PredType::C_S1, value.size() ? value.size() : 1);
          set.createAttribute(key, type, scalar).write(type, value);
        }
        for (const auto& [key, value] : c.number_attributes)
          set.createAttribute(key, H5::PredType::NATIVE_DOUBLE, scalar)
              .write(H5::PredType::NATIVE_DOUBLE, &value);
        if (!c.table_name.empty()) {
          const hsize_t tdims[2] = {static_cast<hsize_t>(c.table.rows()),
                                    static_cast<hsize_t>(c.table.cols())};
          H5::DataSpace tspace(2, tdims);
          detail::write_closed(file.createDataSet(c.table_name, H5::PredType::NATIVE_INT, tspace),
                               c.table.data(), H5::PredType::NATIVE_INT);
        }
        set.close();
        file.close();  // here, where a failure throws, not in the destructor
      } catch (const H5::Exception& e) {
        throw InputError(path, c.name, "HDF5 write failed: " + e.getDetailMsg());
      }
    });
  });
}

}  // namespace eitbench
