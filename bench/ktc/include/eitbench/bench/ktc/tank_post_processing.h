#pragma once
// A post-processing network for the tank (docs/ktc.md#the-post-processing-network): the method
// the challenge's winners used, a network that reads a one-step linearised reconstruction rather
// than the frame. Each frame (a level's missing values NaN) is reconstructed by a model-based
// method of the KTC run at a fixed weight, from the values it has; the image's pixels inside the
// tank are the network's inputs. The same network as tank_network.h otherwise: the same labels,
// levels drawn the same way, the group applied to the full frames before the level's mask.
#include <cstdint>
#include <memory>
#include <string>

#include "eitbench/augment/augmented_set.h"
#include "eitbench/bench/ktc/ktc_method.h"
#include "eitbench/bench/ktc/tank_network.h"
#include "eitbench/bench/ktc/tank_simulation.h"
#include "eitbench/learned/learned_model.h"
#include "eitbench/solvers/missing_values.h"

namespace eitbench {

struct KtcOneStep {
  std::string method = "noser";  // a KTC method (ktc_method_names) that reconstructs in one step
  // Its regularisation on the method's relative scale, fixed beforehand: the middle of the
  // candidates NOSER holds within 1 of its best (0.03 ... 1), not tuned on the samples.
  double lambda = 0.1;

  // InputError("KtcOneStep", field): a one-step Tikhonov-family method or GREIT, lambda positive.
  void validate() const;
};

// The one-step method on the tank (every pattern of missing values built on first use).
std::unique_ptr<MissingValues> make_ktc_one_step(const KtcSetup& setup, const KtcOneStep& step);

// Each frame's one-step image, its pixels inside the tank (setup.grid's mask), one row a frame.
SampleMatrix ktc_one_step_inputs(const MissingValues& one_step, const PixelGrid& grid,
                                 const SampleMatrix& frames);

// `tanks` as ktc_network_frames draws them (the group, a level a row from `seed`), each frame
// replaced by its one-step image's inputs.
LabelledFrames ktc_post_frames(const KtcSimulatedSet& tanks, const CurrentPatterns& patterns,
                               bool group, std::uint64_t seed, const MissingValues& one_step,
                               const PixelGrid& grid);

// What the trainer checks the inputs against: the tank's protocol (recorded in the model file),
// `inputs` pixels as the network's inputs.
AugmentSetup ktc_post_setup(const CurrentPatterns& patterns, int grid, int inputs);

// The classes on KTC's 256 x 256 grid of a change (NaN where a level removed the value).
ClassImage ktc_post_classes(const LearnedModel& model, const MissingValues& one_step,
                            const PixelGrid& grid, const Eigen::VectorXd& change, double threshold);

}  // namespace eitbench
