#include "eitbench/solvers/reconstructor.h"

#include <stdexcept>

#include <tbb/parallel_for.h>

#include <cmath>

#include "eitbench/jacobian/error.h"

namespace eitbench {

const char* to_string(Criterion c) {
  switch (c) {
    case Criterion::fixed:
      return "fixed";
    case Criterion::validation:
      return "validation";
    case Criterion::gcv:
      return "gcv";
    case Criterion::lcurve:
      return "lcurve";
    case Criterion::discrepancy:
      return "discrepancy";
  }
  return "?";
}

Criterion parse_criterion(const std::string& name) {
  for (Criterion c : {Criterion::fixed, Criterion::validation, Criterion::gcv, Criterion::lcurve,
                      Criterion::discrepancy})
    if (name == to_string(c)) return c;
  throw InputError(
      "Criterion", "name",
      "unknown criterion '" + name + "' (fixed, validation, gcv, lcurve or discrepancy)");
}

void check_fixed_or_validation(const char* options, Criterion choice,
                               const std::vector<double>& candidates) {
  if (choice == Criterion::gcv || choice == Criterion::lcurve || choice == Criterion::discrepancy)
    throw InputError(options, "choice",
                     std::string(to_string(choice)) +
                         " needs a one-step linear method; this one is fixed or chosen by "
                         "validation");
  if (choice != Criterion::validation) return;
  if (candidates.empty()) throw InputError(options, "candidates", "validation needs candidates");
  for (double c : candidates)
    if (!(c > 0) || !std::isfinite(c))
      throw InputError(options, "candidates", "every candidate must be positive and finite");
}

void Reconstructor::fit(const SampleMatrix&, const SampleMatrix&, const ScoreFn&) {}

bool Reconstructor::set_regularisation(double, const std::string&) {
  return false;
}

SampleMatrix Reconstructor::reconstruct_all(const SampleMatrix& frames) const {
  if (frames.rows() == 0) return {};
  // Frames are independent: in parallel, with results identical for any thread count.
  const Eigen::VectorXd first = reconstruct(frames.row(0).transpose());
  SampleMatrix images(frames.rows(), first.size());
  images.row(0) = first.transpose();
  tbb::parallel_for(Eigen::Index(1), frames.rows(), [&](Eigen::Index i) {
    images.row(i) = reconstruct(frames.row(i).transpose()).transpose();
  });
  return images;
}

std::vector<Circle> Reconstructor::touches(const Eigen::VectorXd&, Eigen::VectorXd&) const {
  throw std::logic_error(name() + " finds no circles (finds_circles() is false)");
}

std::vector<std::vector<Circle>> Reconstructor::touches_all(const SampleMatrix& frames,
                                                            SampleMatrix& images) const {
  std::vector<std::vector<Circle>> circles(static_cast<std::size_t>(frames.rows()));
  images.resize(frames.rows(), 0);
  if (frames.rows() == 0) return circles;
  Eigen::VectorXd first;
  circles[0] = touches(frames.row(0).transpose(), first);
  images.resize(frames.rows(), first.size());
  images.row(0) = first.transpose();
  tbb::parallel_for(Eigen::Index(1), frames.rows(), [&](Eigen::Index i) {
    Eigen::VectorXd image;
    circles[static_cast<std::size_t>(i)] = touches(frames.row(i).transpose(), image);
    images.row(i) = image.transpose();
  });
  return circles;
}

std::vector<Eigen::Index> Reconstructor::spread_rows(Eigen::Index rows, Eigen::Index at_most) {
  // Every step-th row, the step rounded up so that at most `at_most` are taken.
  const Eigen::Index step = std::max<Eigen::Index>(1, (rows + at_most - 1) / at_most);
  std::vector<Eigen::Index> out;
  for (Eigen::Index i = 0; i < rows; i += step) out.push_back(i);
  return out;
}

double Reconstructor::best_by_score(const std::vector<double>& candidates,
                                    const std::function<void(double)>& set,
                                    const SampleMatrix& frames, const SampleMatrix& labels,
                                    const ScoreFn& score, Eigen::Index max_frames) const {
  if (!score || labels.rows() != frames.rows() || frames.rows() == 0)
    throw InputError("validation frames", "",
                     "choosing by validation needs labelled frames and a score");
  const std::vector<Eigen::Index> rows = spread_rows(frames.rows(), max_frames);
  SampleMatrix some(static_cast<Eigen::Index>(rows.size()), frames.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) some.row(k) = frames.row(rows[k]);
  double best_score = -INFINITY, best = candidates.front();
  for (double candidate : candidates) {
    set(candidate);
    const SampleMatrix images = reconstruct_all(some);
    double total = 0;
    for (std::size_t k = 0; k < rows.size(); ++k)
      total += score(images.row(k).transpose(), labels.row(rows[k]).transpose());
    if (total > best_score) best_score = total, best = candidate;
  }
  // Every score NaN (images or labels without variation): no candidate is better than another.
  if (best_score == -INFINITY)
    throw InputError("validation frames", "", "no candidate could be scored (every score is NaN)");
  return best;
}

}  // namespace eitbench
