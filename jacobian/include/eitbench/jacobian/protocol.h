#pragma once
// The adjacent drive / adjacent measurement protocol of docs/conventions.md, for any L >= 4.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace eitbench {

enum class MeasurementOrder {
  rotating,   // canonical: for drive d, m = d+2, ..., d+L-2 (mod L); L x (L-3) reads as the EIM
  ascending,  // instruments' order: for drive d, m = 0..L-1 skipping d-1, d, d+1
};

// rotating | ascending; InputError("MeasurementOrder", "name") otherwise.
MeasurementOrder parse_order(const std::string& name);
std::string to_string(MeasurementOrder order);

struct MeasurementPair {
  int drive;    // current +I into electrode drive, out of drive+1
  int measure;  // v = u(measure) - u(measure+1)
  bool operator==(const MeasurementPair& o) const {
    return drive == o.drive && measure == o.measure;
  }
};

class Protocol {
 public:
  // L >= 4; InputError("Protocol", "electrodes") otherwise (L is a sensor's, so a user's).
  explicit Protocol(int electrodes);

  int electrodes() const { return electrodes_; }
  int frame_size() const { return electrodes_ * (electrodes_ - 3); }        // 208 for L = 16
  int reduced_size() const { return electrodes_ * (electrodes_ - 3) / 2; }  // 104 for L = 16

  const std::vector<MeasurementPair>& pairs(MeasurementOrder order) const;
  // The reciprocity-reduced values: v(d, m) with d < m, m - d >= 2, (d, m) != (0, L-1), row-major.
  const std::vector<MeasurementPair>& reduced_pairs() const { return reduced_; }

  // Position of (d, m) in a frame of the given order, or -1 when (d, m) is not measured.
  int index(int drive, int measure, MeasurementOrder order) const;
  // Position in the rotating frame of each reduced value; and, for each rotating entry, the
  // reduced value that equals it by reciprocity.
  const std::vector<int>& reduced_to_rotating() const { return reduced_to_rotating_; }
  const std::vector<int>& rotating_to_reduced() const { return rotating_to_reduced_; }

  // A frame (a user's data) of the wrong length is InputError("frame", "values").
  Eigen::VectorXd reorder(const Eigen::VectorXd& frame, MeasurementOrder from,
                          MeasurementOrder to) const;
  Eigen::VectorXd reduce(const Eigen::VectorXd& frame, MeasurementOrder order) const;
  Eigen::VectorXd expand(const Eigen::VectorXd& reduced, MeasurementOrder order) const;
  // Rows of a matrix whose rows follow the rotating order, picked for `order` (or the 104 reduced
  // rows when reduced is true): the same selection the frames get.
  Eigen::MatrixXd select_rows(const Eigen::MatrixXd& rotating_rows, MeasurementOrder order,
                              bool reduced) const;

  // Relative reciprocity error of a full frame: ||v(d,m) - v(m,d)|| / ||v|| over all pairs.
  double reciprocity_error(const Eigen::VectorXd& frame, MeasurementOrder order) const;

 private:
  int electrodes_;
  std::vector<MeasurementPair> rotating_, ascending_, reduced_;
  std::vector<int> rotating_index_;  // L*L table (d, m) -> rotating position or -1
  std::vector<int> ascending_index_;
  std::vector<int> reduced_to_rotating_, rotating_to_reduced_;
};

}  // namespace eitbench
