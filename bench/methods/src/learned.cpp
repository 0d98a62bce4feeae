// The learned reconstructor ("dnn"): trained by training_run.h, which keeps the epoch with the
// lowest validation MSE; nothing is tuned on validation frames afterwards.
#include "eitbench/learned.h"
#include "method_specs.h"

namespace eitbench {
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

MethodSpec methods::learned() {
  MethodSpec spec;
  spec.name = "dnn";
  return spec;  // no make: it needs a model file
}

}  // namespace eitbench
