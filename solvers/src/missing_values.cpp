#include "eitbench/solvers/missing_values.h"

#include <cmath>
#include <stdexcept>

#include "eitbench/jacobian/error.h"

namespace eitbench {

MissingValues::MissingValues(std::shared_ptr<const LinearProblem> full, std::string name, Make make,
                             Eigen::VectorXd noise)
    : full_(require_problem(std::move(full), "MissingValues")),
      name_(std::move(name)),
      make_(std::move(make)),
      noise_(std::move(noise)) {
  if (!full_->rows.empty() || full_->weights.size())
    throw std::invalid_argument("MissingValues: the full problem is already restricted");
  if (!make_) throw std::invalid_argument("MissingValues: no method to build");
  if (noise_.size() && noise_.size() != full_->measurements())
    throw std::invalid_argument("MissingValues: one noise value an input");
  for (Eigen::Index i = 0; i < noise_.size(); ++i)
    if (!(noise_[i] > 0) || !std::isfinite(noise_[i]))
      throw InputError("noise", "value " + std::to_string(i), "must be positive and finite");
}

std::vector<bool> MissingValues::present_values(const Eigen::VectorXd& frame) const {
  full_->check_frame_size(frame.size());
  std::vector<bool> present(static_cast<std::size_t>(frame.size()));
  bool any = false;
  for (Eigen::Index i = 0; i < frame.size(); ++i) {
    if (std::isinf(frame[i]))
      throw InputError("frame", "value " + std::to_string(i),
                       "is infinite (NaN marks a missing value)");
    present[static_cast<std::size_t>(i)] = !std::isnan(frame[i]);
    any = any || present[static_cast<std::size_t>(i)];
  }
  if (!any) throw InputError("frame", "", "has every value missing (NaN)");
  return present;
}

const MissingValues::Built& MissingValues::built(const std::vector<bool>& present) const {
  if (present.size() != static_cast<std::size_t>(full_->measurements()))
    throw std::invalid_argument("MissingValues: one flag an input");
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = built_.find(present);
  if (it != built_.end()) return it->second;
  std::vector<int> rows;
  for (std::size_t i = 0; i < present.size(); ++i)
    if (present[i]) rows.push_back(static_cast<int>(i));
  Eigen::VectorXd weights;
  if (noise_.size()) {
    weights.resize(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t i = 0; i < rows.size(); ++i)
      weights[static_cast<Eigen::Index>(i)] = 1 / noise_[rows[i]];
  }
  Built b;
  b.problem = std::make_shared<const LinearProblem>(
      restrict_problem(*full_, std::move(rows), std::move(weights)));
  b.method = make_(b.problem);
  if (!b.method) throw std::invalid_argument("MissingValues: the method was not built");
  if (regularisation_)
    b.method->set_regularisation(regularisation_->first, regularisation_->second);
  return built_.emplace(present, std::move(b)).first->second;
}

const Reconstructor& MissingValues::method_for(const std::vector<bool>& present) const {
  return *built(present).method;
}

std::map<std::vector<bool>, std::vector<Eigen::Index>> MissingValues::group(
    const SampleMatrix& frames) const {
  std::map<std::vector<bool>, std::vector<Eigen::Index>> groups;
  for (Eigen::Index r = 0; r < frames.rows(); ++r)
    groups[present_values(frames.row(r).transpose())].push_back(r);
  return groups;
}

SampleMatrix MissingValues::data_of(const LinearProblem& problem, const SampleMatrix& frames,
                                    const std::vector<Eigen::Index>& which) {
  SampleMatrix out(static_cast<Eigen::Index>(which.size()), problem.measurements());
  for (std::size_t r = 0; r < which.size(); ++r)
    out.row(static_cast<Eigen::Index>(r)) =
        problem.data_of(frames.row(which[r]).transpose()).transpose();
  return out;
}

std::string MissingValues::settings() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::string out;
  for (const auto& [present, b] : built_) {
    if (!out.empty()) out += "; ";
    out += b.method->settings() + " on " + std::to_string(b.problem->measurements()) + " values";
  }
  return out.empty() ? "no method built yet" : out;
}

void MissingValues::fit(const SampleMatrix& frames, const SampleMatrix& labels,
                        const ScoreFn& score) {
  for (const auto& [present, which] : group(frames)) {
    const Built& b = built(present);
    SampleMatrix picked;  // none for the criteria that need no labels (gcv, lcurve)
    if (labels.rows() == frames.rows()) {
      picked.resize(static_cast<Eigen::Index>(which.size()), labels.cols());
      for (std::size_t r = 0; r < which.size(); ++r)
        picked.row(static_cast<Eigen::Index>(r)) = labels.row(which[r]);
    }
    b.method->fit(data_of(*b.problem, frames, which), picked, score);
  }
}

bool MissingValues::set_regularisation(double relative, const std::string& how) {
  std::lock_guard<std::mutex> lock(mutex_);
  regularisation_ = std::make_pair(relative, how);
  bool all = true;
  for (auto& [present, b] : built_) all = b.method->set_regularisation(relative, how) && all;
  return all;
}

Eigen::VectorXd MissingValues::reconstruct(const Eigen::VectorXd& frame) const {
  const Built& b = built(present_values(frame));
  return b.method->reconstruct(b.problem->data_of(frame));
}

SampleMatrix MissingValues::reconstruct_all(const SampleMatrix& frames) const {
  SampleMatrix images(frames.rows(), full_->grid.num_pixels());
  for (const auto& [present, which] : group(frames)) {
    const Built& b = built(present);
    const SampleMatrix part = b.method->reconstruct_all(data_of(*b.problem, frames, which));
    for (std::size_t r = 0; r < which.size(); ++r)
      images.row(which[r]) = part.row(static_cast<Eigen::Index>(r));
  }
  return images;
}

}  // namespace eitbench
