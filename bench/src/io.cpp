#include "eitbench/bench/io.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <random>
#include <sstream>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace fs = std::filesystem;

namespace {

// False when `pid` is gone, or a zombie that nobody reaped (as in containers without an init).
bool process_alive(pid_t pid) {
  if (::kill(pid, 0) != 0 && errno == ESRCH) return false;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  std::getline(stat, text);
  const auto close = text.rfind(')');
  return !(close != std::string::npos && close + 2 < text.size() && text[close + 2] == 'Z');
}

}  // namespace

std::string temporary_path_for(const std::string& path) {
  if (path.empty()) throw InputError("--out", "", "the output path is empty");
  const fs::path target(path);
  if (fs::is_directory(target)) throw InputError(path, "", "is a directory, expected a file name");
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  if (!fs::is_directory(dir))
    throw InputError(path, "", "the folder " + dir.string() + " does not exist");
  // A process killed while writing (SIGKILL cannot be caught) leaves its temporary behind: the
  // next writer of the same target removes those whose process is gone.
  const std::string prefix = "." + target.stem().string() + ".tmp",
                    suffix = target.extension().string();
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string digits =
        name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::strtol(digits.c_str(), nullptr, 10);
    if (pid > 0 && pid != ::getpid() && !process_alive(static_cast<pid_t>(pid)))
      fs::remove(entry.path(), error);
  }
  return (dir / (prefix + std::to_string(::getpid()) + suffix)).string();
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string&)>& write) {
  const fs::path target(path);
  const fs::path temp = temporary_path_for(path);
  try {
    write(temp.string());
  } catch (...) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw;
  }
  std::error_code error;
  fs::rename(temp, target, error);
  if (error) {
    fs::remove(temp, error);
    throw InputError(path, "", "cannot write the file: " + error.message());
  }
}

void write_text_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
  write_atomically(path, [&](const std::string& temp) {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out)
      throw InputError(path, "", "cannot create the file: " + std::string(std::strerror(errno)));
    write(out);
    out.flush();
    if (!out) throw InputError(path, "", "writing failed (disk full?)");
  });
}

std::string read_file_bytes(const std::string& path, long long max_bytes) {
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  if (error) throw InputError(path, "", "cannot read the file: " + error.message());
  if (size == 0) throw InputError(path, "", "the file is empty");
  if (static_cast<long long>(size) > max_bytes)
    throw InputError(path, "",
                     "the file is " + std::to_string(size) + " bytes, more than the " +
                         std::to_string(max_bytes) + " allowed");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open the file: " + std::string(std::strerror(errno)));
  std::string bytes(size, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (in.gcount() != static_cast<std::streamsize>(size))
    throw InputError(path, "", "the file could not be read whole");
  return bytes;
}

void write_bytes_atomically(const std::string& path, const std::string& bytes) {
  write_text_atomically(path, [&](std::ostream& out) {
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

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
