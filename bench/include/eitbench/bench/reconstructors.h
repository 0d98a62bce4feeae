#pragma once
// Every reconstruction method by its command-line name, built on one linear problem.
#include <memory>
#include <string>
#include <vector>

#include "eitbench/learned.h"
#include "eitbench/solvers.h"

namespace eitbench {

struct MethodOptions {
  std::string choose = "gcv";         // gcv | lcurve | validation | fixed
  double lambda = 0;                  // with choose == fixed
  bool absolute = false;              // gn: absolute frames instead of differences
  std::string neighbours = "pixels";  // laplace: pixels | elements
  double tolerance = 0;               // tv, gn: stopping tolerance (0: the method's default)
};

const std::vector<std::string>& method_names();  // tikhonov noser laplace ... dnn
std::unique_ptr<Reconstructor> make_reconstructor(const std::string& method,
                                                  const LinearProblem& problem,
                                                  const MethodOptions& options);

// The learned reconstructor behind the same interface ("dnn"): fit() does nothing (it was
// trained), reconstruct_all runs in batches.
std::unique_ptr<Reconstructor> make_learned_reconstructor(LearnedModel model);

}  // namespace eitbench
