#include "eitbench/bench/io/csv.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

namespace {

// Calls row(values, line_number) for every line that holds numbers.
template <typename RowFn>
void for_each_csv_row(std::istream& in, const std::string& path, RowFn&& row) {
  std::string line;
  int line_number = 0;
  std::vector<double> values;
  while (std::getline(in, line)) {
    ++line_number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    for (char& c : line)
      if (c == ',' || c == ';' || c == '\t' || c == '\r') c = ' ';
    std::istringstream words(line);
    std::string word;
    values.clear();
    while (words >> word) {
      errno = 0;
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      const std::string field =
          "line " + std::to_string(line_number) + ", value " + std::to_string(values.size() + 1);
      if (*end != '\0' || errno == ERANGE)
        throw InputError(path, field, "'" + word + "' is not a number");
      if (!std::isfinite(v)) throw InputError(path, field, "NaN or infinite");
      values.push_back(v);
    }
    if (!values.empty()) row(values, line_number);
  }
}

std::ifstream open_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open the file");
  return in;
}

}  // namespace

std::vector<double> read_numbers(const std::string& path) {
  std::vector<double> all;
  std::ifstream in = open_text(path);
  for_each_csv_row(in, path, [&](const std::vector<double>& values, int) {
    all.insert(all.end(), values.begin(), values.end());
  });
  return all;
}

Eigen::MatrixXd read_frames_csv(const std::string& path) {
  std::ifstream in = open_text(path);
  return read_frames_csv(in, path);
}

Eigen::MatrixXd read_frames_csv(std::istream& in, const std::string& path) {
  std::vector<std::vector<double>> rows;
  for_each_csv_row(in, path, [&](const std::vector<double>& values, int line) {
    if (!rows.empty() && values.size() != rows.front().size())
      throw InputError(path, "line " + std::to_string(line),
                       "has " + std::to_string(values.size()) + " values, the first frame has " +
                           std::to_string(rows.front().size()));
    rows.push_back(values);
  });
  if (rows.empty()) throw InputError(path, "", "the file holds no frames");
  Eigen::MatrixXd frames(static_cast<Eigen::Index>(rows.size()),
                         static_cast<Eigen::Index>(rows.front().size()));
  for (std::size_t i = 0; i < rows.size(); ++i)
    frames.row(i) = Eigen::Map<const Eigen::RowVectorXd>(rows[i].data(), frames.cols());
  return frames;
}

void write_matrix_csv(const std::string& path, const Eigen::MatrixXd& m) {
  write_text_atomically(path, [&](std::ostream& out) {
    out << std::setprecision(17);
    for (Eigen::Index i = 0; i < m.rows(); ++i) {
      for (Eigen::Index j = 0; j < m.cols(); ++j) out << (j ? "," : "") << m(i, j);
      out << '\n';
    }
  });
}

void write_frames_csv(const std::string& path, const Eigen::MatrixXd& frames_by_row) {
  write_matrix_csv(path, frames_by_row);
}

}  // namespace eitbench
