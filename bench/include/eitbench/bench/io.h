#pragma once
// Files in and out. Every output goes to a temporary beside its target and is renamed into place
// only when complete, so an interrupted or failed run never leaves a half-written file.
#include <Eigen/Core>
#include <functional>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

namespace eitbench {

// Writes `path` through `write(temporary_path)`, then renames. The temporary keeps the target's
// extension (some writers choose the format by it) and is removed when write() throws.
void write_atomically(const std::string& path,
                      const std::function<void(const std::string&)>& write);
// The temporary beside `path` that write_atomically uses (checks that the folder exists).
std::string temporary_path_for(const std::string& path);
void write_text_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write);

// The whole file; InputError naming it when it is missing, unreadable, empty or larger than
// max_bytes (checked before anything is allocated).
std::string read_file_bytes(const std::string& path, long long max_bytes = 4LL << 30);
void write_bytes_atomically(const std::string& path, const std::string& bytes);

// Numbers separated by commas, spaces or newlines ('#' starts a comment). Throws InputError naming
// the file and the line of anything that is not a finite number.
std::vector<double> read_numbers(const std::string& path);

// Frames as CSV: one frame a line (commas or spaces, '#' comments, blank lines skipped). Every line
// must have the same number of finite values; InputError names the file and the line otherwise.
Eigen::MatrixXd read_frames_csv(const std::string& path);
Eigen::MatrixXd read_frames_csv(std::istream& in, const std::string& source);

// Frames as CSV: one frame a line, full precision.
void write_frames_csv(const std::string& path, const Eigen::MatrixXd& frames_by_row);

// A matrix as CSV, one row a line.
void write_matrix_csv(const std::string& path, const Eigen::MatrixXd& matrix);

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
