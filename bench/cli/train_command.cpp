// eitbench train: the learned reconstructor from a data set's training and validation splits.
#include <fmt/core.h>

#include <cstdio>
#include <memory>

#include "commands.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/sensor.h"
#include "eitbench/bench/data/training_data.h"
#include "eitbench/bench/methods/model_file.h"
#include "eitbench/bench/methods/training_run.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/msh_io.h"
#include "eitbench/learned.h"
#include "options.h"

namespace eitbench::cli {

namespace {

// The command line's defaults: early stopping on (the library's default is off).
TrainingOptions default_options() {
  TrainingOptions o;
  o.patience = 5;
  return o;
}

struct TrainArgs {
  std::string data, augment = "none", model = "small", device = "cpu", out, schedule = "cosine",
                    decoder = "pixel_shuffle", mesh;
  ProtocolChoice protocol;
  TrainingOptions options = default_options();
  BudgetRule rule;
  int threads = 2, train_size = 0;
  double dropout = -1;
  bool resume = false, quiet = false;
};

void add_train_options(CLI::App* cmd, TrainArgs* args) {
  cmd->add_option("--data", args->data,
                  "an eitbench data set with labels and train/validation splits (HDF5)")
      ->required();
  add_protocol_options(*cmd, args->protocol);
  cmd->add_option("--mesh", args->mesh,
                  "the sensor's Gmsh mesh, checked against the one the data set was simulated on "
                  "(a set made with simulate --mesh carries it; the disk's carries none)");
  cmd->add_option("--augment", args->augment,
                  "none | rotations (16x) | d16 (D_L, 32x) | paper (the paper's literal mirror) | "
                  "mirror | group (a set on a sensor of another shape: its whole group)")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "rotations", "d16", "dihedral", "paper", "mirror", "group"}));
  auto* epochs = cmd->add_option("--epochs", args->options.epochs,
                                 "budget in epochs, an upper bound (default: 100 small, 300 paper)")
                     ->check(CLI::Range(1, 1000000));
  auto* steps = cmd->add_option("--steps", args->options.steps, "budget in optimiser steps")
                    ->check(CLI::Range(1LL, 1LL << 40));
  epochs->excludes(steps);
  cmd->add_option("--model", args->model,
                  "small (sized for a 2-core CPU) | paper (the paper's widths; GPU advised)")
      ->capture_default_str()
      ->check(CLI::IsMember({"small", "paper"}));
  cmd->add_option("--device", args->device, "auto | cpu | cuda")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  cmd->add_option("--resident", args->options.resident,
                  "keep the training set on the device, a batch one gather there: auto (on a "
                  "GPU when it fits in --resident-max-gib), on, off; the same batches either way")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}));
  cmd->add_option("--resident-max-gib", args->options.resident_max_gib,
                  "device memory the resident set may take, in GiB")
      ->capture_default_str()
      ->check(kPositive);
  cmd->add_option("--precision", args->options.precision,
                  "arithmetic on a GPU: fp32, tf32 (TF32 tensor-core products), bf16 (autocast), "
                  "or auto (tf32 on a GPU, fp32 on the CPU, which has fp32 only)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "fp32", "tf32", "bf16"}));
  cmd->add_option("--cuda-graphs", args->options.cuda_graphs,
                  "capture the training step as a CUDA graph and replay it: auto (on a GPU with "
                  "the resident set), on, off")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}));
  cmd->add_option("--channels-last", args->options.channels_last,
                  "the decoder in channels-last (NHWC) memory, as cuDNN's tensor cores work: on, "
                  "off; the same arithmetic, rounded differently")
      ->capture_default_str()
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_flag("--resume", args->resume,
                "continue the interrupted run whose checkpoint is beside --out (OUT.checkpoint)");
  cmd->add_option("--out", args->out,
                  "model file to write; OUT.checkpoint during training, <stem>_loss.csv/.png "
                  "after")
      ->required();
  cmd->add_option("--batch", args->options.batch_size, "batch size (default: 128 small, 512 paper)")
      ->check(CLI::Range(2, 1 << 20));
  cmd->add_option(
         "--lr", args->options.learning_rate,
         "Adam's peak learning rate (default: 1e-2 small, 1e-3 paper; the paper used 1e-4)")
      ->check(kPositive);
  cmd->add_option("--schedule", args->schedule,
                  "cosine (linear warm-up, a half cosine down to --floor x the peak at --decay "
                  "of the budget, then that floor) | constant")
      ->capture_default_str()
      ->check(CLI::IsMember({"cosine", "constant"}));
  cmd->add_option("--warmup", args->options.schedule.warmup_fraction,
                  "warm-up, as a fraction of the budget's steps")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--decay", args->options.schedule.decay_fraction,
                  "where the cosine reaches its floor, as a fraction of the budget's steps (the "
                  "rest is left for early stopping to find the end)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--floor", args->options.schedule.final_fraction,
                  "the cosine's floor, as a fraction of the peak rate")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--validate-every", args->options.validate_every,
                  "training samples between two validations (and checkpoints)")
      ->capture_default_str()
      ->check(CLI::Range(1LL, 1LL << 40));
  cmd->add_option("--decoder", args->decoder,
                  "pixel_shuffle (each convolution at half its output size: fast) | nearest "
                  "(upsample, then convolve; the decoder of models made before pixel_shuffle)")
      ->capture_default_str()
      ->check(CLI::IsMember({"pixel_shuffle", "nearest"}));
  cmd->add_option("--dropout", args->dropout, "dropout after the encoder's hidden layers")
      ->check(CLI::Range(0.0, 0.95));
  cmd->add_option("--patience", args->options.patience,
                  "stop after N validations without a validation loss --min-improvement below "
                  "the last improvement (0: train to the budget)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  cmd->add_option("--doublings", args->rule.max_doublings,
                  "after the budget, continue from the best model over as many steps again "
                  "(the budget doubles) while the last doubling lowered the best validation loss "
                  "by more than --doubling-tolerance, at most this many times (docs/learned.md)")
      ->capture_default_str()
      ->check(CLI::Range(0, 20));
  cmd->add_option("--doubling-tolerance", args->rule.tolerance,
                  "the relative drop of the best validation loss a doubling must bring for another")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.99));
  cmd->add_option("--min-improvement", args->options.min_improvement,
                  "the relative drop of the validation loss that counts as an improvement")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.5));
  cmd->add_flag("--expanded", args->options.expanded,
                "materialise every sample under every group element (an epoch sees all |G| N) "
                "instead of one random element per sample and epoch");
  cmd->add_option("--train-size", args->train_size,
                  "use N training samples only, drawn at random by --seed (nested: a smaller N "
                  "draws a subset of a larger one)")
      ->check(CLI::Range(2, 1 << 30));
  cmd->add_option("--seed", args->options.seed, "seed of weights, batch order and augmentation")
      ->capture_default_str();
  cmd->add_option("--threads", args->threads,
                  "LibTorch threads; results are bit-identical for a seed and a thread count")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("--quiet", args->quiet, "no progress output");
}

// The options a flag left unset take the model size's defaults.
TrainingOptions training_options(TrainArgs& args, const CLI::App& cmd, ModelSize size) {
  TrainingOptions o = args.options;
  o.augment = parse_group(args.augment, "--augment");
  o.device = resolve_device(args.device, "--device");
  o.schedule.kind = parse_schedule(args.schedule, "--schedule");
  if (!cmd.count("--batch")) o.batch_size = size == ModelSize::paper ? 512 : 128;
  if (!cmd.count("--lr")) o.learning_rate = size == ModelSize::paper ? 1e-3 : 1e-2;
  if (!cmd.count("--epochs") && !cmd.count("--steps"))
    o.epochs = size == ModelSize::paper ? 300 : 100;
  o.validate();  // before the data are read: flags that disagree (--warmup, --decay) fail at once
  return o;
}

void print_result(const TrainArgs& args, const TrainingResult& r) {
  const TrainingRecord& best = r.history[r.best_round > 0 ? r.best_round - 1 : 0];
  double samples = 0, seconds = 0;
  for (const auto& e : r.history) samples += e.samples_per_second * e.seconds, seconds += e.seconds;
  fmt::print(
      "{} rounds, {} steps ({} an epoch; {} doublings, ended by {}), {}; best round {} (epoch "
      "{}): validation MSE {:.5g}; {:.0f} samples/s\n",
      r.history.size(), r.history.back().steps, r.steps_per_epoch, r.doublings, to_string(r.end),
      r.converged ? "converged" : "NOT converged: its budget or its schedule's floor ended it",
      r.best_round, r.best_epoch, best.validation_loss, seconds > 0 ? samples / seconds : 0.0);
  fmt::print("wrote {} ({} parameters), {} and {}\n", args.out, r.model.parameters(),
             loss_curve_path(args.out, "csv"), loss_curve_path(args.out, "png"));
}

}  // namespace

std::function<void()> add_train_command(CLI::App& app) {
  auto args = std::make_shared<TrainArgs>();
  auto* cmd = app.add_subcommand(
      "train", "Train the learned reconstructor (MLP encoder, CNN decoder) on a data set");
  add_train_options(cmd, args.get());
  return [args, cmd] {
    const ModelSize size = parse_model_size(args->model, "--model");
    const TrainingOptions o = training_options(*args, *cmd, size);
    set_torch_threads(args->threads);
    if (const std::string warning = thread_layout().warning(); !warning.empty())
      fmt::print(stderr, "warning: {}\n", warning);

    const Dataset data = read_dataset(args->data);
    if (!data.has_labels())
      throw InputError(args->data, "labels", "training needs labelled data (a simulated set)");
    LabelledFrames train =
        labelled_frames(data, Split::train, args->train_size, args->options.seed);
    const LabelledFrames validation = labelled_frames(data, Split::validation);
    if (train.frames.rows() == 0)
      throw InputError(args->data, "split", "the training split is empty");
    if (validation.frames.rows() == 0)
      throw InputError(args->data, "split", "the validation split is empty");
    NetworkOptions network =
        NetworkOptions::preset(size, static_cast<int>(data.differences.cols()), data.image_size);
    network.radius = data.radius;
    check_protocol_of(args->protocol, measurement_protocol(data), args->data);
    if (!args->mesh.empty() && mesh_text(read_msh_file(args->mesh)) != data.sensor_mesh)
      throw InputError(args->mesh, "",
                       data.sensor_mesh.empty()
                           ? "the data set was simulated on the disk, not on this mesh"
                           : "is not the mesh the data set was simulated on (simulate --mesh "
                             "stores it; leave out --mesh to use it)");
    network.mask = sensor_mask(data);  // a sensor of another shape masks to its own
    if (args->dropout >= 0) network.dropout = args->dropout;
    if (parse_upsampling(args->decoder, "--decoder") == Upsampling::nearest) {
      // The same widths, with the decoder's last stage at full size (a channel per stage more).
      network.upsampling = Upsampling::nearest;
      network.decoder_channels.push_back(std::max(1, network.decoder_channels.back() / 2));
    }

    const long long train_count = train.frames.rows();
    if (!args->quiet)
      fmt::print(
          "training the {} model ({:.1f} MFLOP a frame) on {} samples (augmentation {}{}), "
          "{} validation; device {}, {} threads\n",
          args->model, forward_flops(network) / 1e6, train_count, to_string(o.augment),
          o.expanded ? ", expanded" : ", on the fly", validation.frames.rows(), o.device,
          torch_threads());
    std::fflush(stdout);  // before the progress on stderr
    TrainingRun run;
    run.out = args->out;
    run.resume = args->resume;
    run.quiet = args->quiet;
    run.rule = args->rule;
    const TrainingResult r =
        train_and_save(network, o, std::move(train), validation, sensor_of(data), run);
    print_result(*args, r);
  };
}

}  // namespace eitbench::cli
