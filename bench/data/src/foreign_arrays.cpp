#include "foreign_arrays.h"

#include <cctype>
#include <filesystem>
#include <limits>

#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/csv.h"
#include "eitbench/bench/io/matlab.h"
#include "eitbench/bench/io/numpy.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/input_file.h"

namespace eitbench::detail {

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// The arrays of a file and how it was read.
std::vector<NamedArray> read_arrays(const std::string& path,
                                    const std::function<bool(std::size_t)>& fits,
                                    std::size_t longest, std::string& format, bool& columns_first) {
  require_input_file(path);
  const std::string ext = lower_extension(path);
  columns_first = false;
  if (ext == ".npy") {
    format = "NumPy .npy";
    return {read_npy(eitbench::read_file_bytes(path), path, "")};
  }
  if (ext == ".npz") {
    format = "NumPy .npz";
    return read_npz(eitbench::read_file_bytes(path), path);
  }
  if (ext == ".mat") {
    columns_first = true;
    if (eitbench::is_hdf5_file(path)) {
      format = "MATLAB v7.3";
      return read_mat_v73(path);
    }
    format = "MATLAB v5";
    return read_mat_v5(eitbench::read_file_bytes(path), path);
  }
  if (ext == ".csv" || ext == ".txt") {
    format = "CSV";
    // A frame a line, or (a width no frame has) a frame a column of at most `longest` lines.
    const Eigen::MatrixXd m = read_frames_csv(path, [&](std::size_t width, int) {
      return fits(width) ? std::numeric_limits<std::size_t>::max() : longest;
    });
    NamedArray a;
    a.shape = {static_cast<std::size_t>(m.rows()), static_cast<std::size_t>(m.cols())};
    a.values.resize(m.size());
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      for (Eigen::Index j = 0; j < m.cols(); ++j) a.values[i * m.cols() + j] = m(i, j);
    return {a};
  }
  if (ext == ".h5" || ext == ".hdf5")
    throw InputError(path, "", "not an HDF5 file (no HDF5 signature): empty, or another format");
  throw InputError(
      path, "",
      "unknown file type '" + ext + "' (.csv, .txt, .npy, .npz, .mat or an eitbench .h5)");
}

const NamedArray& choose(const std::vector<NamedArray>& arrays, const std::string& variable,
                         const std::string& path, const std::vector<std::string>& preferred) {
  std::string names;
  for (const auto& a : arrays)
    names += (names.empty() ? "" : ", ") + a.name + (a.numeric ? "" : " (" + a.kind + ")");
  if (!variable.empty()) {
    for (const auto& a : arrays)
      if (a.name == variable) {
        if (!a.numeric)
          throw InputError(path, variable, "is a " + a.kind + ", not a numeric matrix of frames");
        return a;
      }
    throw InputError(path, variable, "no such variable; the file holds: " + names);
  }
  std::vector<const NamedArray*> numeric;
  for (const auto& a : arrays)
    if (a.numeric) numeric.push_back(&a);
  if (numeric.size() == 1) return *numeric.front();
  for (const std::string& name : preferred)
    for (const auto* a : numeric)
      if (a->name == name) return *a;
  throw InputError(path, "variables",
                   numeric.empty()
                       ? "no numeric matrix; the file holds: " + names
                       : "several candidates (" + names + "): choose one with --variable");
}

}  // namespace eitbench::detail
