#pragma once
// Internal: scalar HDF5 attributes as every eitbench file writes them (strings are variable-length
// UTF-8, which h5py reads as str and MATLAB's h5readatt as char), and data sets written and closed.
#include <H5Cpp.h>

#include <cstdint>
#include <string>

namespace eitbench::detail {

inline void write_attribute(H5::H5Object& at, const std::string& name, const std::string& value) {
  H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
  type.setCset(H5T_CSET_UTF8);
  at.createAttribute(name, type, H5::DataSpace(H5S_SCALAR)).write(type, value);
}
inline void write_attribute(H5::H5Object& at, const std::string& name, double value) {
  at.createAttribute(name, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR))
      .write(H5::PredType::NATIVE_DOUBLE, &value);
}
inline void write_attribute(H5::H5Object& at, const std::string& name, long long value) {
  at.createAttribute(name, H5::PredType::NATIVE_LLONG, H5::DataSpace(H5S_SCALAR))
      .write(H5::PredType::NATIVE_LLONG, &value);
}
inline void write_attribute(H5::H5Object& at, const std::string& name, std::uint64_t value) {
  at.createAttribute(name, H5::PredType::NATIVE_UINT64, H5::DataSpace(H5S_SCALAR))
      .write(H5::PredType::NATIVE_UINT64, &value);
}

// Writes `data` into `set` and closes it here, where a failure throws. A DataSet's destructor only
// prints what fails (a full disk found when its last chunk is flushed), and the file would pass
// for complete: every writer closes its data sets, then its file, explicitly.
inline void write_closed(H5::DataSet set, const void* data, const H5::PredType& type) {
  set.write(data, type);
  set.close();
}

}  // namespace eitbench::detail
