#pragma once
// The benchmark's reconstructors by their command-line names: for each, how it is built on the
// linear problem and how the benchmark tunes it (each method's file says how it chooses its
// hyperparameter; the candidates live in the solver). One file a method in bench/methods/src/; a
// new method is that file and one line in registry.cpp.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "eitbench/learned.h"
#include "eitbench/solvers.h"

namespace eitbench {

// What the command line and the benchmark ask of a method.
struct MethodOptions {
  // fixed | validation | gcv | lcurve | discrepancy, or empty for the method's default_choice. A
  // method refuses a criterion it cannot use (InputError naming its options' "choice").
  std::string choose;
  double lambda = 0;  // with choose == fixed; 0: the method's default value
  // With choose == discrepancy: the frames' noise, the RMS over a frame's values in the frames'
  // units (TikhonovOptions::noise), and Morozov's factor on it.
  double noise = 0;
  double discrepancy_factor = 1;
  // The Tikhonov family's fixed lambda as a multiple of its scale (TikhonovOptions::relative);
  // the other methods' lambdas are relative already.
  bool relative_lambda = false;
  bool absolute = false;              // gn: absolute frames instead of differences
  std::string neighbours = "pixels";  // laplace: pixels | elements
  double noser_exponent = 0.5;        // noser: p of diag(A^T A)^p (TikhonovOptions)
  double smooth_length = 1.0;  // smooth: where its covariance falls to 1 %, in grid radii (ditto)
  double tolerance = 0;        // tv, gn: stopping tolerance (0: the method's default)
  double robust = 0;  // shape: Huber's loss at this multiple of the start's residual RMS (0: none)
};

struct MethodSpec {
  std::string name;  // on the command line, in results.json and the report
  // The benchmark tunes it on at most RunConfig::sweep_frames validation frames instead of all:
  // the iterative methods, whose sweep costs a solve per frame and candidate.
  bool sweep_on_subset = false;
  // What an empty MethodOptions::choose means: gcv for the one-step Tikhonov family (frames
  // alone choose lambda), fixed at the documented default for the rest.
  std::string default_choice = "fixed";
  // Its result is a pixel image of the conductivity change, whose extreme places a press (every
  // model-based method but the shape fits, whose result is a circle).
  bool pixel_image = false;
  // It reconstructs a frame by one linear map, fixed once built (the Tikhonov family, GREIT): what
  // a training set's thousands of frames can afford.
  bool one_step = false;
  // Null for a method that is trained, not built on the linear problem (dnn).
  std::function<std::unique_ptr<Reconstructor>(std::shared_ptr<const LinearProblem>,
                                               const MethodOptions&)>
      make;
};

// Every method, in the order the benchmark runs and reports them.
const std::vector<MethodSpec>& method_registry();
// tikhonov noser laplace smooth tv gn greit shape shape-linear dnn
const std::vector<std::string>& method_names();
// The methods with a property (&MethodSpec::pixel_image, &MethodSpec::one_step), in registry
// order, and the same as one "a, b, c" for messages.
std::vector<std::string> method_names_with(bool MethodSpec::*property);
std::string joined_method_names_with(bool MethodSpec::*property);
// Those built on the linear problem (every method but the trained one): the benchmark's --methods.
std::vector<std::string> model_based_method_names();
// The spec of `name`; InputError naming --method for an unknown one.
const MethodSpec& find_method(const std::string& name);
// find_method(name).make; InputError naming --model for dnn (it needs a trained model).
std::unique_ptr<Reconstructor> make_reconstructor(const std::string& name,
                                                  std::shared_ptr<const LinearProblem> problem,
                                                  const MethodOptions& options);

// The learned reconstructor behind the same interface ("dnn"): fit() does nothing (it was
// trained), reconstruct_all runs in batches.
std::unique_ptr<Reconstructor> make_learned_reconstructor(LearnedModel model);

}  // namespace eitbench
