#pragma once
// Numbers and frames as text: one frame a line, values separated by commas, spaces or tabs.
#include <Eigen/Core>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace eitbench {

// Numbers separated by commas, spaces or newlines ('#' starts a comment). Throws InputError naming
// the file and the line of anything that is not a finite number.
std::vector<double> read_numbers(const std::string& path);

// What a reader of frames accepts, asked on the first line, before the rest of the file is read:
// given the first frame's width (and its line), the most lines the caller can use at that width;
// an InputError refuses the file there (a 40 MB file of one value a line stops at line 1).
using CsvWidthCheck = std::function<std::size_t(std::size_t width, int line)>;

// Frames as CSV: one frame a line (commas or spaces, '#' comments, blank lines skipped). Every line
// must have the same number of finite values; InputError names the file and the line otherwise.
// Streamed, within the memory rule of eitbench/jacobian/read_budget.h.
Eigen::MatrixXd read_frames_csv(const std::string& path, const CsvWidthCheck& check = {});
Eigen::MatrixXd read_frames_csv(std::istream& in, const std::string& source,
                                const CsvWidthCheck& check = {});

// Frames as CSV: one frame a line, full precision.
void write_frames_csv(const std::string& path, const Eigen::MatrixXd& frames_by_row);

// A matrix as CSV, one row a line.
void write_matrix_csv(const std::string& path, const Eigen::MatrixXd& matrix);

}  // namespace eitbench
