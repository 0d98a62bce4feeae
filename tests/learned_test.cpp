// The learned reconstructor: training, its augmentation, checkpoints and the model file.
#include <gtest/gtest.h>

#include <cmath>

#include "eitbench/augment.h"
#include "eitbench/bench/data/simulate.h"
#include "eitbench/bench/data/training_data.h"
#include "eitbench/jacobian.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/learned.h"
#include "learned_support.h"

namespace eitbench {
namespace {

using testing::test_network;
using testing::tiny;

double mse(const SampleMatrix& a, const SampleMatrix& b) {
  return (a - b).squaredNorm() / a.size();
}

TEST(Network, FlopsCountMultiplyAddsOfEveryLayer) {
  NetworkOptions n;  // the default small network, by hand: pixel shuffle, 8 -> 16 -> 32 -> 64
  const double linear = 104.0 * 256 + 256.0 * 32 * 64;
  // Each convolution runs at half its output size to 4x the channels: 9 c (4 c') (side / 2)^2.
  const double shuffle = 9.0 * (32 * 16 * 16 * 16 + 16 * 8 * 32 * 32 + 8 * 1 * 64 * 64);
  EXPECT_DOUBLE_EQ(forward_flops(n), 2 * (linear + shuffle));
  n.image_size = 32;  // 8 * 2^3 != 32
  EXPECT_THROW(check_network_options(n, "test"), InputError);
  NetworkOptions nearest;  // upsample, then convolve at full size; a last convolution to 1 channel
  nearest.upsampling = Upsampling::nearest;
  nearest.decoder_channels = {16, 8, 4};
  const double conv =
      9.0 * (32 * 16 * 16 * 16 + 16 * 8 * 32 * 32 + 8 * 4 * 64 * 64) + 9.0 * 4 * 64 * 64;
  EXPECT_DOUBLE_EQ(forward_flops(nearest), 2 * (linear + conv));
  EXPECT_NO_THROW(check_network_options(nearest, "test"));
  nearest.decoder_channels = {16, 8};  // two stages: 8 * 2^2 != 64
  EXPECT_THROW(check_network_options(nearest, "test"), InputError);
}

// Both decoders draw n x n images; a model file from before the choice existed (no "upsampling"
// in its network description) is the nearest-upsampling network it was trained as.
TEST(Network, BothDecodersAndOldModelFiles) {
  NetworkOptions nearest = test_network();
  nearest.upsampling = Upsampling::nearest;
  nearest.decoder_channels = {8, 4, 4};
  const SampleMatrix frames = labelled_frames(tiny(), Split::validation).frames.topRows(3);
  for (const NetworkOptions& n : {test_network(), nearest}) {
    const LearnedModel model(n, 16, 1);
    EXPECT_EQ(model.reconstruct(frames).cols(), 64 * 64);
    const LearnedModel back = LearnedModel::from_bytes(model.to_bytes(), "memory");
    EXPECT_EQ(back.info().network.upsampling, n.upsampling);
    EXPECT_EQ(back.reconstruct(frames), model.reconstruct(frames));
  }
}

TEST(Trainer, SmallModelOverfits64Samples) {
  const Dataset& data = tiny();
  const LabelledFrames train = labelled_frames(data, Split::train, 64);
  ASSERT_EQ(train.frames.rows(), 60);  // the tiny preset has 60: all of them
  NetworkOptions n = test_network();
  n.dropout = 0;
  TrainingOptions o;
  o.batch_size = 20;
  o.learning_rate = 3e-3;
  // Memorising needs no annealing: a constant rate fits these 60 samples in the fewest steps
  // (600; the pixel-shuffle decoder of this thin test network needs more of them than the
  // nearest-upsampling one did, 180).
  o.schedule.kind = ScheduleKind::constant;
  o.epochs = 200;
  o.validate_every = 60 * 10;  // every 10 epochs
  Trainer trainer(n, o, train, train, sensor_of(data));
  const double before = mse(trainer.best_model().reconstruct(train.frames), train.labels);
  while (!trainer.done()) trainer.run_round();
  const double after = mse(trainer.best_model().reconstruct(train.frames), train.labels);
  std::printf("overfitting 60 samples: MSE %.4g -> %.4g (%.0fx)\n", before, after, before / after);
  EXPECT_LT(after, before / 10);
  // The validation loss the trainer records is the model's MSE on those frames.
  EXPECT_NEAR(trainer.history()[trainer.best_round() - 1].validation_loss, after, 1e-6 * after);
}

TEST(Trainer, SaveAndLoadGiveIdenticalOutputs) {
  const Dataset& data = tiny();
  TrainingOptions o;
  o.epochs = 2;
  o.batch_size = 16;
  Trainer trainer(test_network(), o, labelled_frames(data, Split::train),
                  labelled_frames(data, Split::validation), sensor_of(data));
  while (!trainer.done()) trainer.run_round();
  const LearnedModel model = trainer.best_model();
  const LearnedModel loaded = LearnedModel::from_bytes(model.to_bytes(), "memory");
  const SampleMatrix frames = labelled_frames(data, Split::test).frames;
  const SampleMatrix a = model.reconstruct(frames), b = loaded.reconstruct(frames);
  EXPECT_EQ(a, b);
  EXPECT_EQ(loaded.info().electrodes, 16);
  EXPECT_EQ(loaded.info().network.hidden, test_network().hidden);
  EXPECT_NE(loaded.info().training.find("\"best_epoch\""), std::string::npos);
  // One frame at a time gives the batch's rows (evaluation mode: no batch statistics).
  EXPECT_LT(
      (model.reconstruct(Eigen::VectorXd(frames.row(3).transpose())) - a.row(3).transpose()).norm(),
      1e-5 * a.row(3).norm());
  // Outside the disk the image is exactly zero.
  const PixelGrid grid(64, 1.0);
  for (Eigen::Index p = 0; p < a.cols(); ++p) {
    if (!grid.mask()[p]) {
      ASSERT_EQ(a(0, p), 0.0);
    }
  }
}

// D_16, batch 16 (4 steps an epoch on the tiny set), a round of 3 steps (rounds straddle epochs).
TrainingOptions dihedral_rounds_of_three(long long steps) {
  TrainingOptions o;
  o.augment = AugmentGroup::dihedral;
  o.steps = steps;
  o.batch_size = 16;
  o.validate_every = 48;
  return o;
}

TEST(Trainer, ResumedRunMatchesUninterruptedRun) {
  const Dataset& data = tiny();
  const LabelledFrames train = labelled_frames(data, Split::train),
                       validation = labelled_frames(data, Split::validation);
  const TrainingOptions o = dihedral_rounds_of_three(10);  // epochs 1, 2 and half of 3
  Trainer whole(test_network(), o, train, validation, sensor_of(data));
  while (!whole.done()) whole.run_round();
  ASSERT_EQ(whole.history().size(), 4u);
  EXPECT_EQ(whole.history().back().steps, 10);
  EXPECT_EQ(whole.history().back().epoch, 3);

  std::string checkpoint;
  {
    Trainer first(test_network(), o, train, validation, sensor_of(data));
    first.run_round();
    checkpoint = first.checkpoint();
  }  // "killed" after round 1, in the middle of epoch 1
  auto resumed = Trainer::resume(checkpoint, "checkpoint", train, validation, sensor_of(data));
  while (!resumed->done()) resumed->run_round();
  ASSERT_EQ(resumed->history().size(), 4u);
  for (int e = 0; e < 4; ++e) {
    EXPECT_EQ(resumed->history()[e].train_loss, whole.history()[e].train_loss) << "round " << e;
    EXPECT_EQ(resumed->history()[e].validation_loss, whole.history()[e].validation_loss);
  }
  const SampleMatrix frames = validation.frames;
  EXPECT_EQ(resumed->best_model().reconstruct(frames), whole.best_model().reconstruct(frames));

  // A checkpoint resumes only on its own data.
  LabelledFrames other = train;
  other.frames(0, 0) += 1e-9;
  EXPECT_THROW(Trainer::resume(checkpoint, "checkpoint", other, validation, sensor_of(data)),
               InputError);
  // Nor on other circles or another background: augmented samples' labels are drawn from them.
  ASSERT_FALSE(train.circles.empty());
  other = train;
  other.circles[0][0].r *= 1.01;
  EXPECT_THROW(Trainer::resume(checkpoint, "checkpoint", other, validation, sensor_of(data)),
               InputError);
  other = train;
  other.background *= 2;
  EXPECT_THROW(Trainer::resume(checkpoint, "checkpoint", other, validation, sensor_of(data)),
               InputError);
}

// A channels-last training resumes exactly, as the NCHW one does, and trains as the NCHW one
// up to rounding: the layout changes no arithmetic, only its order.
TEST(Trainer, ChannelsLastResumesExactlyAndTrainsAsNchw) {
  const Dataset& data = tiny();
  const LabelledFrames train = labelled_frames(data, Split::train),
                       validation = labelled_frames(data, Split::validation);
  TrainingOptions o = dihedral_rounds_of_three(9);  // 3 rounds
  Trainer nchw(test_network(), o, train, validation, sensor_of(data));
  while (!nchw.done()) nchw.run_round();
  o.channels_last = "on";
  Trainer whole(test_network(), o, train, validation, sensor_of(data));
  while (!whole.done()) whole.run_round();
  std::string checkpoint;
  {
    Trainer first(test_network(), o, train, validation, sensor_of(data));
    first.run_round();
    checkpoint = first.checkpoint();
  }
  auto resumed = Trainer::resume(checkpoint, "checkpoint", train, validation, sensor_of(data));
  while (!resumed->done()) resumed->run_round();
  ASSERT_EQ(whole.history().size(), 3u);
  ASSERT_EQ(resumed->history().size(), 3u);
  ASSERT_EQ(nchw.history().size(), 3u);
  for (int r = 0; r < 3; ++r) {
    EXPECT_EQ(resumed->history()[r].train_loss, whole.history()[r].train_loss) << "round " << r;
    EXPECT_EQ(resumed->history()[r].validation_loss, whole.history()[r].validation_loss);
    const double v = nchw.history()[r].validation_loss;
    EXPECT_NEAR(whole.history()[r].validation_loss, v, 1e-4 * v) << "round " << r;
  }
  // The models' images agree to 1e-3, not to the losses' 1e-5: the biases of the layers before a
  // BatchNorm have gradients of rounding noise, which Adam scales up to whole steps; the norm
  // removes them in training, but in evaluation its running means trail them. (A wrong layout
  // would give another image altogether.)
  const SampleMatrix frames = validation.frames;
  const SampleMatrix a = whole.best_model().reconstruct(frames),
                     b = nchw.best_model().reconstruct(frames);
  EXPECT_LT((a - b).norm(), 3e-3 * b.norm());
}

TEST(Trainer, OnTheFlyPairsEachFrameWithItsLabel) {
  // Each training sample as the network receives it must be a frame and label of the same
  // touch: find the circles whose exact label it is, simulate them, compare with the frame.
  const Dataset& data = tiny();
  const LabelledFrames train = labelled_frames(data, Split::train);
  TrainingOptions o;
  o.augment = AugmentGroup::dihedral;
  o.batch_size = 12;
  Trainer trainer(test_network(), o, train, labelled_frames(data, Split::validation),
                  sensor_of(data));
  DiskMeshOptions disk;
  disk.density = MeshDensity::coarse;  // the mesh the tiny set was simulated on
  const Mesh mesh = generate_disk_mesh(disk);
  const ForwardModel model(mesh, {});
  const PixelGrid grid(64, 1.0);
  const Eigen::VectorXd reference =
      model.frame(Eigen::VectorXd::Constant(mesh.num_triangles(), data.background));
  const auto elements = group_elements(AugmentGroup::dihedral, 16);
  SampleMatrix frames, labels;
  int non_identity = 0;
  for (int epoch : {1, 2}) {
    trainer.batch(epoch, 0, frames, labels);
    for (Eigen::Index k = 0; k < frames.rows(); ++k) {
      std::vector<Circle> found;
      int which = -1;
      for (int i = 0; i < train.frames.rows() && which < 0; ++i)
        for (std::size_t e = 0; e < elements.size() && which < 0; ++e) {
          const auto moved = transform_circles(train.circles[i], elements[e], 16);
          // Stored labels are float32 (the file's type); moved ones are drawn afresh in double.
          const Eigen::VectorXd drawn = circles_image(grid, moved, data.background);
          if ((drawn - labels.row(k).transpose()).norm() < 1e-6 * drawn.norm()) {
            found = moved, which = static_cast<int>(e);
          }
        }
      ASSERT_GE(which, 0) << "row " << k << ": the label is no transformed training label";
      non_identity += which != 0;
      const Eigen::VectorXd simulated = model.protocol().reduce(
          model.frame(conductivity_from_circles(mesh, found, data.background)) - reference,
          MeasurementOrder::rotating);
      EXPECT_LT((simulated - frames.row(k).transpose()).norm(), 1e-8 * simulated.norm())
          << "epoch " << epoch << " row " << k << " element " << elements[which].to_string();
    }
  }
  EXPECT_GT(non_identity, 12);  // 24 draws from 32 elements: nearly all move the touch
}

TEST(Trainer, InputStatisticsAreThoseOfTheAugmentedSet) {
  const Dataset& data = tiny();
  const LabelledFrames train = labelled_frames(data, Split::train);
  for (AugmentGroup group :
       {AugmentGroup::none, AugmentGroup::rotations, AugmentGroup::dihedral, AugmentGroup::paper}) {
    TrainingOptions o;
    o.augment = group;
    const Trainer trainer(test_network(), o, train, labelled_frames(data, Split::validation),
                          sensor_of(data));
    LabelledFrames frames_only;
    frames_only.frames = train.frames;
    const SampleMatrix all = expand_by_group(frames_only, sensor_of(data, group)).frames;
    const Eigen::VectorXd mean = all.colwise().mean().transpose();
    const Eigen::VectorXd std =
        ((all.rowwise() - mean.transpose()).colwise().squaredNorm() / double(all.rows()))
            .cwiseSqrt()
            .transpose();
    EXPECT_LT((trainer.input_mean() - mean).norm(), 1e-10 * mean.norm() + 1e-300)
        << to_string(group);
    EXPECT_LT((trainer.input_std() - std).norm(), 1e-10 * std.norm()) << to_string(group);
  }
  // Under D_L the statistics are invariant: measurements in one orbit share mean and deviation.
  TrainingOptions o;
  o.augment = AugmentGroup::dihedral;
  const Trainer d16(test_network(), o, train, labelled_frames(data, Split::validation),
                    sensor_of(data));
  const FrameSymmetry symmetry(16);
  for (const GroupElement& g : group_elements(AugmentGroup::dihedral, 16)) {
    EXPECT_LT((symmetry.apply(g, d16.input_std(), FrameLayout::reduced) - d16.input_std()).norm(),
              1e-12 * d16.input_std().norm())
        << g.to_string();
    EXPECT_LT((symmetry.apply(g, d16.input_mean(), FrameLayout::reduced) - d16.input_mean()).norm(),
              1e-12 * d16.input_mean().norm())
        << g.to_string();
  }
}

TEST(Trainer, SameSeedSameModel) {
  const Dataset& data = tiny();
  TrainingOptions o;
  o.augment = AugmentGroup::rotations;
  o.epochs = 2;
  o.batch_size = 16;
  auto run = [&] {
    Trainer t(test_network(), o, labelled_frames(data, Split::train),
              labelled_frames(data, Split::validation), sensor_of(data));
    while (!t.done()) t.run_round();
    return t.best_model().reconstruct(labelled_frames(data, Split::test).frames);
  };
  EXPECT_EQ(run(), run());
  // Across LibTorch thread counts the float reductions run in another order: the same model to
  // float rounding (bit-identical results hold per thread count, which the CLI fixes at 2 by
  // default; see README "Determinism").
  const int threads = torch_threads();
  set_torch_threads(1);
  const SampleMatrix one = run();
  set_torch_threads(2);
  const SampleMatrix two = run();
  set_torch_threads(threads);
  std::printf("1 vs 2 threads: max difference %.3g\n", (one - two).cwiseAbs().maxCoeff());
  EXPECT_LT((one - two).cwiseAbs().maxCoeff(), 1e-3 * one.cwiseAbs().maxCoeff());
}

// The step callback reads the loss at most 64 times a round (each read is a device sync), and what
// it reports adds up to the round's training loss; a callback changes nothing in the training.
TEST(Trainer, StepCallbackIsThinnedAndAddsUpToTheRoundLoss) {
  const Dataset& data = tiny();
  TrainingOptions o;
  o.epochs = 10;
  o.batch_size = 4;
  o.validate_every = 1 << 20;  // one round: the whole budget
  auto trainer = [&] {
    return Trainer(test_network(), o, labelled_frames(data, Split::train),
                   labelled_frames(data, Split::validation), sensor_of(data));
  };
  Trainer with = trainer(), without = trainer();
  long long calls = 0, last = 0, total_steps = 0;
  double weighted = 0;
  const TrainingRecord r = with.run_round([&](long long step, long long steps, double loss) {
    EXPECT_GT(step, last);
    weighted += loss * double(step - last), last = step, total_steps = steps, ++calls;
  });
  ASSERT_GT(total_steps, 64);  // enough steps for the thinning to show
  EXPECT_LE(calls, 64);
  EXPECT_EQ(last, total_steps);  // the last step is always reported
  EXPECT_NEAR(weighted / double(total_steps), r.train_loss, 1e-12 * r.train_loss);
  const TrainingRecord plain = without.run_round();
  EXPECT_EQ(plain.train_loss, r.train_loss);
  EXPECT_EQ(plain.validation_loss, r.validation_loss);
}

// The resident path (the set on the device, a batch one gather there) is the host path's batches,
// converted to float32 once instead of each step: the same batches, hence the same training.
TEST(Trainer, ResidentSetGivesTheHostPathsBatchesAndTraining) {
  const Dataset& data = tiny();
  const LabelledFrames train = labelled_frames(data, Split::train),
                       validation = labelled_frames(data, Split::validation);
  for (bool expanded : {false, true}) {
    TrainingOptions o;
    o.augment = AugmentGroup::dihedral;
    o.expanded = expanded;
    o.steps = 6;
    o.batch_size = 16;
    o.validate_every = 48;
    TrainingOptions on = o, off = o;
    on.resident = "on", off.resident = "off";
    Trainer resident(test_network(), on, train, validation, sensor_of(data));
    Trainer host(test_network(), off, train, validation, sensor_of(data));
    SampleMatrix f1, l1, f2, l2;
    for (int epoch : {1, 3})
      for (long long index : {0LL, resident.steps_per_epoch() - 1}) {
        resident.batch(epoch, index, f1, l1);
        host.batch(epoch, index, f2, l2);
        ASSERT_EQ(f1.rows(), f2.rows());
        // float32 on the device, double on the host: equal to float rounding.
        EXPECT_LT((f1 - f2).cwiseAbs().maxCoeff(), 1e-6 * f2.cwiseAbs().maxCoeff())
            << "expanded " << expanded << " epoch " << epoch << " batch " << index;
        EXPECT_LT((l1 - l2).cwiseAbs().maxCoeff(), 1e-6 * l2.cwiseAbs().maxCoeff());
      }
    while (!resident.done()) resident.run_round();
    while (!host.done()) host.run_round();
    ASSERT_EQ(resident.history().size(), host.history().size());
    for (std::size_t r = 0; r < host.history().size(); ++r) {
      EXPECT_EQ(resident.history()[r].train_loss, host.history()[r].train_loss) << r;
      EXPECT_EQ(resident.history()[r].validation_loss, host.history()[r].validation_loss) << r;
    }
  }
  // "on" beyond its budget says so; "auto" falls back to the host path.
  TrainingOptions tight;
  tight.augment = AugmentGroup::dihedral;
  tight.resident = "on";
  tight.resident_max_gib = 1e-6;
  EXPECT_THROW(Trainer(test_network(), tight, train, validation, sensor_of(data)), InputError);
  tight.resident = "auto";
  EXPECT_NO_THROW(Trainer(test_network(), tight, train, validation, sensor_of(data)));
  tight.resident = "always";
  EXPECT_THROW(Trainer(test_network(), tight, train, validation, sensor_of(data)), InputError);
}

TEST(Trainer, BadInputIsRefused) {
  const Dataset& data = tiny();
  const LabelledFrames train = labelled_frames(data, Split::train);
  LabelledFrames empty = train;
  empty.frames.resize(0, train.frames.cols());
  empty.labels.resize(0, train.labels.cols());
  empty.circles.clear();
  LabelledFrames unlabelled;
  unlabelled.frames = train.frames;
  const TrainingOptions o;
  EXPECT_THROW(Trainer(test_network(), o, empty, train, sensor_of(data)), InputError);
  EXPECT_THROW(Trainer(test_network(), o, train, empty, sensor_of(data)), InputError);
  EXPECT_THROW(Trainer(test_network(), o, unlabelled, train, sensor_of(data)), InputError);
  NetworkOptions wide = test_network();
  wide.inputs = 208;
  EXPECT_THROW(Trainer(wide, o, train, train, sensor_of(data)), InputError);
  TrainingOptions cuda;
  cuda.device = "cuda";
  if (!cuda_available()) {
    EXPECT_THROW(Trainer(test_network(), cuda, train, train, sensor_of(data)), InputError);
  }
}

// The GPU options name their field, and the CPU, which has fp32 only and no graphs, refuses them.
TEST(Trainer, GpuOptionsAreCheckedOnTheCpu) {
  auto field_of = [](const TrainingOptions& o) {
    try {
      o.validate();
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("accepted");
  };
  TrainingOptions o;
  EXPECT_EQ(field_of(o), "accepted");  // auto and auto: fp32, no graphs on the CPU
  o.precision = "fp32", o.cuda_graphs = "off";
  EXPECT_EQ(field_of(o), "accepted");
  for (const char* bad : {"tf32", "bf16", "fp16"}) {
    o.precision = bad;
    EXPECT_EQ(field_of(o), "precision") << bad;
  }
  o.precision = "auto";
  for (const char* bad : {"on", "yes"}) {
    o.cuda_graphs = bad;
    EXPECT_EQ(field_of(o), "cuda_graphs") << bad;
  }
  o.cuda_graphs = "auto", o.channels_last = "on";  // a layout: the CPU has it too
  EXPECT_EQ(field_of(o), "accepted");
  o.channels_last = "auto";
  EXPECT_EQ(field_of(o), "channels_last");
}

TEST(LearnedModel, CorruptBytesAreRefused) {
  const LearnedModel model(test_network(), 16, 1);
  const std::string bytes = model.to_bytes();
  EXPECT_NO_THROW(LearnedModel::from_bytes(bytes, "good"));
  EXPECT_THROW(LearnedModel::from_bytes("", "empty"), InputError);
  EXPECT_THROW(LearnedModel::from_bytes(bytes.substr(0, bytes.size() / 2), "truncated"),
               InputError);
  std::string flipped = bytes;
  for (std::size_t k = 100; k < flipped.size(); k += 97)
    flipped[k] = static_cast<char>(~flipped[k]);
  EXPECT_THROW(LearnedModel::from_bytes(flipped, "flipped"), InputError);
  EXPECT_THROW(LearnedModel::from_bytes("plain text, not a model", "text"), InputError);
  // A module's TorchScript code damaged (the fuzzer's finding): its parser throws
  // torch::jit::ErrorReport, which is not a c10::Error.
  std::string code = bytes;
  const std::size_t at = code.find("class Module(Module):");
  ASSERT_NE(at, std::string::npos);
  code[at + std::string("class Module(Module").size()] = '!';
  EXPECT_THROW(LearnedModel::from_bytes(code, "code"), InputError);
  // A training checkpoint is not a model file.
  const Dataset& data = tiny();
  const Trainer t(test_network(), {}, labelled_frames(data, Split::train),
                  labelled_frames(data, Split::validation), sensor_of(data));
  try {
    LearnedModel::from_bytes(t.checkpoint(), "model.pt");
    FAIL() << "a checkpoint loaded as a model";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model.pt"), std::string::npos);
  }
  SampleMatrix wrong = SampleMatrix::Zero(2, 103);
  EXPECT_THROW(model.reconstruct(wrong), InputError);
  // The electrode count must be a protocol's (at least 4) and give the network's input size.
  for (int electrodes : {3, 17}) {
    const LearnedModel odd(test_network(), electrodes, 1);
    try {
      LearnedModel::from_bytes(odd.to_bytes(), "odd.pt");
      FAIL() << electrodes << " electrodes with a 104-input network loaded";
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), "odd.pt");
      EXPECT_TRUE(e.field() == "electrodes" || e.field() == "network") << e.what();
    }
  }
}

}  // namespace
}  // namespace eitbench
