#pragma once
// A trained network with everything needed to use it: its shape, the input normalisation it was
// trained with (stored inside the network), the sensor it was trained for, and how it was trained.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "eitbench/jacobian/measurement_protocol.h"
#include "eitbench/jacobian/sample_matrix.h"
#include "eitbench/learned/network_options.h"
#include "eitbench/learned/runtime.h"

namespace eitbench {

struct ModelInfo {
  NetworkOptions network;
  int electrodes = 16;
  std::string augment = "none";  // the group it was trained with
  // The protocol its frames were read on (the network's inputs are this protocol's); null: the
  // adjacent protocol (model files from before protocols).
  std::shared_ptr<const MeasurementProtocol> protocol;
  // Positive: the network reads this many pixels of a one-step image made from the protocol's
  // frames (AugmentSetup::image_inputs), not the frames. 0: frames.
  int image_inputs = 0;
  std::string training = "{}";  // JSON: the training options, budget, history, best epoch
};

class LearnedModel {
 public:
  // A freshly initialised network (weights from `seed`), input mean 0 and scale 1.
  LearnedModel(const NetworkOptions& network, int electrodes, std::uint64_t seed);
  ~LearnedModel();
  LearnedModel(const LearnedModel&);  // a deep copy
  LearnedModel& operator=(const LearnedModel&);
  LearnedModel(LearnedModel&&) noexcept;
  LearnedModel& operator=(LearnedModel&&) noexcept;

  const ModelInfo& info() const;
  // info().protocol, or the adjacent protocol of info().electrodes.
  MeasurementProtocol protocol() const;
  ModelInfo& info();
  long long parameters() const;
  // The pixels the model draws (its decoder's mask, n^2): the disk's, or a sensor's own shape.
  std::vector<bool> image_mask() const;
  // Frames (N x inputs, the protocol's inputs, difference voltages) -> images (N x n^2, 0 outside
  // the disk), in evaluation mode, in batches of `batch`. InputError("frames") on a wrong length.
  SampleMatrix reconstruct(const SampleMatrix& frames, int batch = 512) const;
  Eigen::VectorXd reconstruct(const Eigen::VectorXd& frame) const;
  // Runs on "cpu" or "cuda" (see resolve_device).
  void to_device(const std::string& device);
  std::string device() const;

  // The model file's bytes (a LibTorch archive; bench/ writes them to disk), and back.
  // from_bytes throws InputError(source, ...) on anything that is not such a model.
  std::string to_bytes() const;
  static LearnedModel from_bytes(const std::string& bytes, const std::string& source);

  struct Impl;  // what the LibTorch module implements (learned/src/backend.h)

 private:
  friend class Trainer;  // fills a new model's network with the best one it trained
  Impl& impl() { return *impl_; }
  const Impl& impl() const { return *impl_; }

  explicit LearnedModel(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace eitbench
