#include "eitbench/bench/ktc/ktc_files.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>

#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/matlab.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/input_file.h"

namespace eitbench {
namespace {

std::vector<detail::NamedArray> read_mat(const std::string& path) {
  require_input_file(path);
  return is_hdf5_file(path) ? detail::read_mat_v73(path)
                            : detail::read_mat_v5(read_file_bytes(path), path);
}

// The first of `names` the file holds, numeric; InputError naming the first otherwise.
const detail::NamedArray& variable(const std::vector<detail::NamedArray>& arrays,
                                   const std::vector<std::string>& names, const std::string& path) {
  for (const std::string& n : names)
    for (const auto& a : arrays)
      if (a.name == n) {
        if (!a.numeric) throw InputError(path, n, "is a " + a.kind + ", not a numeric matrix");
        return a;
      }
  std::string held;
  for (const auto& a : arrays) held += (held.empty() ? "" : ", ") + a.name;
  std::string wanted = names.front();
  for (std::size_t k = 1; k < names.size(); ++k) wanted += " or " + names[k];
  throw InputError(path, names.front(),
                   "missing: KTC's file holds " + wanted + "; this one " + held);
}

Eigen::MatrixXd matrix(const detail::NamedArray& a, const std::string& path) {
  if (a.shape.size() != 2)
    throw InputError(path, a.name,
                     "is not a matrix (" + std::to_string(a.shape.size()) + " dimensions)");
  Eigen::MatrixXd m(static_cast<Eigen::Index>(a.shape[0]), static_cast<Eigen::Index>(a.shape[1]));
  for (std::size_t i = 0; i < a.shape[0]; ++i)
    for (std::size_t j = 0; j < a.shape[1]; ++j)
      m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = a.values[i * a.shape[1] + j];
  return m;
}

}  // namespace

KtcMeasurement read_ktc_measurement(const std::string& path) {
  const auto arrays = read_mat(path);
  const auto& u = variable(arrays, {"Uel", "Uelref"}, path);
  const auto& inj = variable(arrays, {"Inj", "Injref"}, path);
  const auto& mpat = variable(arrays, {"Mpat"}, path);
  KtcMeasurement m;
  m.path = path;
  m.patterns.injection = matrix(inj, path);
  m.patterns.measurement = matrix(mpat, path);
  m.patterns.validate(path, inj.name, mpat.name);
  const Eigen::MatrixXd v = matrix(u, path);
  if (v.cols() != 1 && v.rows() != 1)
    throw InputError(path, u.name,
                     "is " + std::to_string(v.rows()) + " x " + std::to_string(v.cols()) +
                         "; one column of voltages expected");
  if (v.size() != m.patterns.size())
    throw InputError(path, u.name,
                     "has " + std::to_string(v.size()) + " values; " + inj.name +
                         " and Mpat imply " + std::to_string(m.patterns.patterns()) +
                         " patterns x " + std::to_string(m.patterns.differences()) +
                         " differences = " + std::to_string(m.patterns.size()));
  m.voltages = Eigen::Map<const Eigen::VectorXd>(v.data(), v.size());
  for (Eigen::Index i = 0; i < m.voltages.size(); ++i)
    if (std::isinf(m.voltages[i]))
      throw InputError(path, u.name,
                       "value " + std::to_string(i) + " is infinite (NaN marks a missing one)");
  return m;
}

ClassImage read_ktc_truth(const std::string& path) {
  const auto arrays = read_mat(path);
  const Eigen::MatrixXd t = matrix(variable(arrays, {"truth"}, path), path);
  if (t.rows() != kKtcImageSize || t.cols() != kKtcImageSize)
    throw InputError(path, "truth",
                     "is " + std::to_string(t.rows()) + " x " + std::to_string(t.cols()) +
                         "; 256 x 256 expected");
  ClassImage out(t.rows(), t.cols());
  for (Eigen::Index i = 0; i < t.rows(); ++i)
    for (Eigen::Index j = 0; j < t.cols(); ++j) {
      const double c = t(i, j);
      if (!(c == 0 || c == 1 || c == 2))
        throw InputError(path, "truth",
                         "holds " + std::to_string(c) + " at (" + std::to_string(i) + ", " +
                             std::to_string(j) + "); classes are 0, 1 and 2");
      out(i, j) = static_cast<std::uint8_t>(c);
    }
  return out;
}

void write_ktc_reconstruction(const std::string& path, const ClassImage& reconstruction) {
  if (reconstruction.rows() != kKtcImageSize || reconstruction.cols() != kKtcImageSize)
    throw InputError(path, "reconstruction", "must be 256 x 256");
  if (reconstruction.size() && reconstruction.maxCoeff() > 2)
    throw InputError(path, "reconstruction", "classes are 0, 1 and 2");
  detail::MatMatrix m;
  m.name = "reconstruction";
  m.rows = m.cols = kKtcImageSize;
  m.values.assign(reconstruction.data(), reconstruction.data() + reconstruction.size());
  m.uint8 = true;
  write_bytes_atomically(path, detail::mat_v5_bytes({m}));
}

KtcFolder scan_ktc_folder(const std::string& folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(folder, "", "is not a folder (KTC's data: ref.mat and dataN.mat files)");
  KtcFolder out;
  const fs::path ref = fs::path(folder) / "ref.mat";
  if (!fs::is_regular_file(ref, ec))
    throw InputError(folder, "ref.mat", "missing: the empty tank's reference measurement");
  out.reference = ref.string();
  const std::regex data_name("data([1-9][0-9]{0,5})\\.mat");
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    std::smatch match;
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file(ec) || !std::regex_match(name, match, data_name)) continue;
    KtcFolder::Sample s;
    s.number = std::stoi(match[1].str());
    s.data = entry.path().string();
    const fs::path truth = fs::path(folder) / ("true" + match[1].str() + ".mat");
    if (fs::is_regular_file(truth, ec)) s.truth = truth.string();
    out.samples.push_back(std::move(s));
  }
  if (out.samples.empty())
    throw InputError(folder, "dataN.mat", "missing: no measurement to reconstruct");
  std::sort(out.samples.begin(), out.samples.end(),
            [](const auto& a, const auto& b) { return a.number < b.number; });
  return out;
}

}  // namespace eitbench
