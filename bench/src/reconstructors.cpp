#include "eitbench/bench/reconstructors.h"

#include "eitbench/jacobian/error.h"

namespace eitbench {

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names{"tikhonov", "noser", "laplace", "tv",
                                              "gn",       "greit", "dnn"};
  return names;
}

std::unique_ptr<Reconstructor> make_reconstructor(const std::string& method,
                                                  const LinearProblem& problem,
                                                  const MethodOptions& o) {
  if (method == "tikhonov" || method == "noser" || method == "laplace") {
    TikhonovOptions t;
    t.prior = parse_prior(method);
    t.choice = o.choose == "fixed" ? Choice::fixed : parse_choice(o.choose);
    t.lambda = o.lambda;
    t.neighbours = parse_neighbours(o.neighbours);
    return std::make_unique<Tikhonov>(problem, t);
  }
  if (method == "tv") {
    // GCV and the L-curve are defined for linear methods only; TV keeps its default weight then.
    TotalVariationOptions t;
    if (o.choose == "fixed") t.alpha = o.lambda;
    t.choose_by_validation = o.choose == "validation";
    if (o.tolerance > 0) t.tolerance = o.tolerance;
    t.neighbours = parse_neighbours(o.neighbours);
    return std::make_unique<TotalVariation>(problem, t);
  }
  if (method == "gn") {
    GaussNewtonOptions g;
    if (o.choose == "fixed") g.lambda = o.lambda;
    g.choose_by_validation = o.choose == "validation";
    g.absolute = o.absolute;
    if (o.tolerance > 0) g.tolerance = o.tolerance;
    return std::make_unique<GaussNewton>(problem, g);
  }
  if (method == "greit") {
    GreitOptions g;
    if (o.choose == "fixed") g.lambda = o.lambda;
    g.choose_by_validation = o.choose == "validation";
    return std::make_unique<Greit>(problem, g);
  }
  if (method == "dnn")
    throw InputError("--model", "", "the dnn method needs a trained model (eitbench train)");
  throw InputError("--method", "", "unknown method '" + method + "'");
}

namespace {

class LearnedReconstructor : public Reconstructor {
 public:
  explicit LearnedReconstructor(LearnedModel model) : model_(std::move(model)) {}
  std::string name() const override { return "dnn"; }
  std::string settings() const override {
    return "augment=" + model_.info().augment + ", " + std::to_string(model_.parameters()) +
           " parameters";
  }
  Eigen::VectorXd reconstruct(const Eigen::VectorXd& frame) const override {
    return model_.reconstruct(frame);
  }
  SampleMatrix reconstruct_all(const SampleMatrix& frames) const override {
    return model_.reconstruct(frames);
  }

 private:
  LearnedModel model_;
};

}  // namespace

std::unique_ptr<Reconstructor> make_learned_reconstructor(LearnedModel model) {
  return std::make_unique<LearnedReconstructor>(std::move(model));
}

}  // namespace eitbench
