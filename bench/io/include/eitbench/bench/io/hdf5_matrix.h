#pragma once
// A matrix as an HDF5 file, for h5py and MATLAB users (the Jacobian command's output).
#include <Eigen/Core>
#include <map>
#include <string>

namespace eitbench {

// A matrix as an HDF5 data set (C order: rows are rows), with scalar attributes on the data set and
// an optional integer table beside it. Readable by h5py and MATLAB.
struct Hdf5Matrix {
  std::string name;
  const Eigen::MatrixXd* matrix = nullptr;
  std::map<std::string, std::string> text_attributes;
  std::map<std::string, double> number_attributes;
  std::string table_name;                                                     // e.g. "pairs"
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> table;  // e.g. drive, measure
};
void write_hdf5_matrix(const std::string& path, const Hdf5Matrix& content);

}  // namespace eitbench
