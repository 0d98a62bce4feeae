#pragma once
// Numbers and frames as text: one frame a line, values separated by commas, spaces or tabs.
#include <Eigen/Core>
#include <iosfwd>
#include <string>
#include <vector>

namespace eitbench {

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

}  // namespace eitbench
