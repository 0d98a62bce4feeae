#pragma once
// Frames with values missing: each frame is reconstructed from the values it has, by the method
// built on the linear problem restricted to them (restrict_problem: those rows of A and of the data
// term, no value invented). A value is missing where the frame holds NaN; removing electrodes, as
// KTC2023's levels do, is one case. The data term may also weight each value by its noise.
#include <Eigen/Core>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "eitbench/solvers/linear_problem.h"
#include "eitbench/solvers/reconstructor.h"

namespace eitbench {

class MissingValues : public Reconstructor {
 public:
  using Make = std::function<std::unique_ptr<Reconstructor>(std::shared_ptr<const LinearProblem>)>;

  // `full` uses every input with weight 1 (make_linear_problem); `make` builds the method on a
  // restricted problem; `noise` is each input's noise standard deviation (positive and finite;
  // empty: every value weighs alike). std::invalid_argument for a restricted `full`, a null
  // `make` or a noise of the wrong size; InputError("noise", "value N") for a bad noise value.
  MissingValues(std::shared_ptr<const LinearProblem> full, std::string name, Make make,
                Eigen::VectorXd noise = {});

  std::string name() const override { return name_; }
  // The settings of each method built so far, by how many values it had.
  std::string settings() const override;
  // Fits one method per pattern of missing values among `frames`, on the frames of that pattern
  // (with their rows of `labels`; labels may be empty for a criterion that needs none).
  void fit(const SampleMatrix& frames, const SampleMatrix& labels, const ScoreFn& score) override;
  // Sets it on every method built and on each built later; false when a built one has none.
  bool set_regularisation(double relative, const std::string& how) override;
  // A frame of the protocol's inputs, NaN where a value is missing. InputError("frame", ...) for
  // another length, an infinite value, or a frame with every value missing.
  Eigen::VectorXd reconstruct(const Eigen::VectorXd& frame) const override;
  // Frames grouped by their pattern of missing values, each group in one call of its method.
  SampleMatrix reconstruct_all(const SampleMatrix& frames) const override;

  // The method for frames whose present values are `present` (built and kept on first use).
  const Reconstructor& method_for(const std::vector<bool>& present) const;
  // A frame's present values (finite), checked as reconstruct() does.
  std::vector<bool> present_values(const Eigen::VectorXd& frame) const;

 private:
  struct Built {
    std::shared_ptr<const LinearProblem> problem;  // restricted to the present values
    std::shared_ptr<Reconstructor> method;
  };
  const Built& built(const std::vector<bool>& present) const;
  // Row indices of `frames` grouped by their pattern of present values.
  std::map<std::vector<bool>, std::vector<Eigen::Index>> group(const SampleMatrix& frames) const;
  // The rows `which` of `frames` as the restricted problem's data (selected, weighted).
  static SampleMatrix data_of(const LinearProblem& problem, const SampleMatrix& frames,
                              const std::vector<Eigen::Index>& which);

  std::shared_ptr<const LinearProblem> full_;
  std::string name_;
  Make make_;
  Eigen::VectorXd noise_;
  mutable std::mutex mutex_;  // guards built_: reconstruct() may build a method from any thread
  mutable std::map<std::vector<bool>, Built> built_;
  std::optional<std::pair<double, std::string>> regularisation_;  // set on each method built
};

}  // namespace eitbench
