#include "eitbench/bench/io/csv.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/input_file.h"
#include "eitbench/jacobian/read_budget.h"

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
    values.clear();
    const char* p = line.c_str();
    for (;;) {
      while (*p == ' ') ++p;
      if (*p == '\0') break;
      const char* word_end = p;
      while (*word_end != ' ' && *word_end != '\0') ++word_end;
      errno = 0;
      char* end = nullptr;
      const double v = std::strtod(p, &end);
      const std::string field =
          "line " + std::to_string(line_number) + ", value " + std::to_string(values.size() + 1);
      if (end != word_end || errno == ERANGE)
        throw InputError(path, field, "'" + std::string(p, word_end) + "' is not a number");
      if (!std::isfinite(v)) throw InputError(path, field, "NaN or infinite");
      values.push_back(v);
      p = word_end;
    }
    if (!values.empty()) row(values, line_number);
  }
}

std::ifstream open_text(const std::string& path) {
  require_input_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open the file");
  return in;
}

}  // namespace

std::vector<double> read_numbers(const std::string& path) {
  std::vector<double> all;
  std::ifstream in = open_text(path);
  ReadBudget budget(path);
  for_each_csv_row(in, path, [&](const std::vector<double>& values, int line) {
    budget.take("line " + std::to_string(line), values.size() * sizeof(double));
    all.insert(all.end(), values.begin(), values.end());
  });
  return all;
}

Eigen::MatrixXd read_frames_csv(const std::string& path, const CsvWidthCheck& check) {
  std::ifstream in = open_text(path);
  return read_frames_csv(in, path, check);
}

Eigen::MatrixXd read_frames_csv(std::istream& in, const std::string& path,
                                const CsvWidthCheck& check) {
  // One flat buffer, grown line by line: the file is never held twice, and a width the caller
  // cannot use stops the read at the first line.
  std::vector<double> all;
  std::size_t width = 0, rows = 0, max_rows = std::numeric_limits<std::size_t>::max();
  ReadBudget budget(path);
  for_each_csv_row(in, path, [&](const std::vector<double>& values, int line) {
    const std::string field = "line " + std::to_string(line);
    if (rows == 0) {
      width = values.size();
      if (check) max_rows = check(width, line);
    } else if (values.size() != width) {
      throw InputError(path, field,
                       "has " + std::to_string(values.size()) + " values, the first frame has " +
                           std::to_string(width));
    }
    if (rows == max_rows)
      throw InputError(path, field,
                       "one line more than the " + std::to_string(max_rows) + " that frames of " +
                           std::to_string(width) + " values can fill");
    budget.take(field, width * sizeof(double));
    all.insert(all.end(), values.begin(), values.end());
    ++rows;
  });
  if (rows == 0) throw InputError(path, "", "the file holds no frames");
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      all.data(), static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(width));
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
