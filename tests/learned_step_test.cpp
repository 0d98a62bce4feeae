// The GPU training step's arithmetic on the CPU: Adam on device tensors (adam_update, what a
// replayed CUDA graph runs) against LibTorch's torch::optim::Adam, and the step runner's graph
// path against its eager path. The capture itself needs a GPU (docs/gpu.md); what it replays is
// this. Includes LibTorch and learned/'s internal train_step.h.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <algorithm>

#include "learned_support.h"
#include "train_step.h"

namespace eitbench {
namespace {

using testing::test_network;  // dropout 0.1: both paths must draw the same masks

// max |a - b| over max |a|, over every tensor of the lists.
double relative_difference(const std::vector<torch::Tensor>& a,
                           const std::vector<torch::Tensor>& b) {
  double difference = 0, scale = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    difference = std::max(difference, (a[k] - b[k]).abs().max().item<double>());
    scale = std::max(scale, a[k].abs().max().item<double>());
  }
  return difference / scale;
}

std::vector<torch::Tensor> detached(const std::vector<torch::Tensor>& params) {
  std::vector<torch::Tensor> out;
  for (const auto& p : params) out.push_back(p.detach().clone());
  return out;
}

// Two copies of the test network with the same weights, each with its own Adam, for two step
// runners (batch 16) to train side by side.
struct TwinNetworks {
  static Network seeded() {
    torch::manual_seed(5);
    return Network(test_network());
  }
  TrainingOptions options = [] {
    TrainingOptions o;
    o.batch_size = 16;
    return o;
  }();
  Network first = seeded(), second = seeded();
  torch::optim::Adam first_adam{first->parameters(), torch::optim::AdamOptions(1e-3)};
  torch::optim::Adam second_adam{second->parameters(), torch::optim::AdamOptions(1e-3)};
};

// Each network's images of `frames`, under the same dropout draws.
std::pair<torch::Tensor, torch::Tensor> images_of(Network& a, Network& b,
                                                  const torch::Tensor& frames) {
  torch::manual_seed(7);
  const auto first = a->forward(frames);
  torch::manual_seed(7);
  return {first, b->forward(frames)};
}

// Six steps under a changing learning rate, the same gradients for both (a function of the
// parameters, so the trajectories would part if either step differed).
TEST(TrainStep, AdamOnTensorsIsLibTorchsAdam) {
  torch::manual_seed(3);
  std::vector<torch::Tensor> a = {torch::randn({5, 3}), torch::randn({7})}, b;
  for (auto& p : a) b.push_back(p.clone().requires_grad_()), p.requires_grad_();
  const auto start = detached(a);
  torch::optim::Adam reference(a, torch::optim::AdamOptions(1e-2));
  torch::optim::Adam holder(b, torch::optim::AdamOptions(1e-2));
  std::vector<torch::Tensor> exp_avg, exp_avg_sq;
  for (const auto& p : b) {
    auto& state = adam_state(holder, p);  // made here: holder has not stepped
    EXPECT_EQ(state.step(), 0);
    exp_avg.push_back(state.exp_avg()), exp_avg_sq.push_back(state.exp_avg_sq());
  }
  const auto step = torch::zeros({}, torch::kFloat64), lr = torch::zeros({}, torch::kFloat64);
  for (int k = 1; k <= 6; ++k) {
    const double rate = 1e-2 * k;
    for (auto& p : a) p.mutable_grad() = torch::sin(3 * p.detach()) * k;
    for (auto& p : b) p.mutable_grad() = torch::sin(3 * p.detach()) * k;
    static_cast<torch::optim::AdamOptions&>(reference.param_groups()[0].options()).lr(rate);
    reference.step();
    lr.fill_(rate);
    adam_update(b, exp_avg, exp_avg_sq, step, lr, 0.9, 0.999, 1e-8);
  }
  EXPECT_GT(relative_difference(start, detached(a)), 0.05);  // the parameters did move
  EXPECT_LT(relative_difference(detached(a), detached(b)), 1e-6);
  EXPECT_EQ(step.item<double>(), 6);
  // The moments are Adam's own: the reference's state, found by adam_state, holds the same.
  for (std::size_t k = 0; k < a.size(); ++k) {
    auto& state = adam_state(reference, a[k]);
    EXPECT_EQ(state.step(), 6);  // found, not made anew
    EXPECT_LT(relative_difference({state.exp_avg()}, {exp_avg[k]}), 1e-6);
    EXPECT_LT(relative_difference({state.exp_avg_sq()}, {exp_avg_sq[k]}), 1e-6);
  }
}

// The graph path's steps (Adam on tensors; eager on the CPU, replayed on a GPU) train the network
// as the eager path's torch::optim::Adam does, dropout included, and leave Adam's step counters
// where a checkpoint expects them.
TEST(TrainStep, GraphPathTrainsAsTheEagerPath) {
  TwinNetworks twins;
  Network &eager_net = twins.first, &graph_net = twins.second;
  torch::optim::Adam& graph_adam = twins.second_adam;
  StepRunner eager(eager_net, twins.first_adam, twins.options, torch::kCPU, false);
  StepRunner graph(graph_net, graph_adam, twins.options, torch::kCPU, true);
  ASSERT_TRUE(graph.graphs());
  const auto start = detached(eager_net->parameters());
  torch::manual_seed(11);
  const auto x = torch::randn({8, 16, 104}), y = torch::rand({8, 16, 64 * 64});
  for (int k = 0; k < 8; ++k) {
    const double rate = 1e-3 * (1 + k % 3);
    torch::manual_seed(100 + k);
    eager.step(x[k], y[k], rate);
    torch::manual_seed(100 + k);
    graph.step(x[k], y[k], rate);
  }
  EXPECT_GT(relative_difference(start, detached(eager_net->parameters())), 1e-3);
  // The networks compute the same function. Not every parameter agrees: the biases of the layers
  // before a BatchNorm have gradients of rounding noise (the norm removes them), which Adam
  // scales up to whole steps, so a last-bit difference between the two paths moves them apart
  // without changing what the network computes.
  const auto [eager_images, graph_images] = images_of(eager_net, graph_net, x[0]);
  EXPECT_LT(relative_difference({eager_images}, {graph_images}), 1e-5);
  const double eager_loss = eager.loss_sum().item<double>();
  EXPECT_NEAR(graph.loss_sum().item<double>(), eager_loss, 1e-6 * eager_loss);
  graph.sync_optimizer();
  for (const auto& p : graph_net->parameters()) EXPECT_EQ(adam_state(graph_adam, p).step(), 8);
}

// The channels-last decoder's pixel shuffle moves the same values as LibTorch's, forwards and
// backwards, and leaves them channels-last (LibTorch's returns NCHW on a GPU).
TEST(Network, ChannelsLastPixelShuffleIsLibTorchsKeepingTheLayout) {
  torch::manual_seed(2);
  const auto nhwc = torch::randn({2, 12, 3, 5}).contiguous(torch::MemoryFormat::ChannelsLast);
  const auto x = nhwc.clone().requires_grad_(), reference = nhwc.contiguous().requires_grad_();
  ASSERT_FALSE(x.is_contiguous());
  const auto out = pixel_shuffle_keeping_layout(x, 2);
  const auto expected = torch::pixel_shuffle(reference, 2);
  ASSERT_EQ(out.sizes(), expected.sizes());  // [2, 3, 6, 10]
  EXPECT_TRUE(out.is_contiguous(torch::MemoryFormat::ChannelsLast));
  EXPECT_FALSE(out.is_contiguous());
  EXPECT_TRUE(torch::equal(out, expected));  // a permutation: exact
  const auto upstream = torch::randn(expected.sizes());
  out.backward(upstream);
  expected.backward(upstream);
  EXPECT_TRUE(torch::equal(x.grad(), reference.grad()));
  // An NCHW input is LibTorch's case.
  EXPECT_TRUE(torch::equal(pixel_shuffle_keeping_layout(reference.detach(), 2), expected));
}

// A network whose decoder is channels-last, stepped by the graph path's Adam on tensors, trains
// as the NCHW network under the eager torch::optim::Adam: the same function, rounded otherwise.
// Its convolution weights and their moments are channels-last, the layout the fused kernel wants.
TEST(TrainStep, ChannelsLastTrainsAsNchw) {
  TwinNetworks twins;
  Network &nchw_net = twins.first, &nhwc_net = twins.second;
  nhwc_net->use_channels_last(true);
  ASSERT_TRUE(nhwc_net->channels_last());
  torch::optim::Adam& nhwc_adam = twins.second_adam;
  StepRunner nchw(nchw_net, twins.first_adam, twins.options, torch::kCPU, false);
  StepRunner nhwc(nhwc_net, nhwc_adam, twins.options, torch::kCPU, true);
  int convolutions = 0;
  for (const auto& p : nhwc_net->decoder->parameters())
    if (p.dim() == 4) {
      ++convolutions;
      EXPECT_FALSE(p.is_contiguous());
      EXPECT_TRUE(p.is_contiguous(torch::MemoryFormat::ChannelsLast));
      EXPECT_EQ(adam_state(nhwc_adam, p).exp_avg().strides(), p.strides());
    }
  EXPECT_EQ(convolutions, 3);
  const auto start = detached(nchw_net->parameters());
  torch::manual_seed(11);
  const auto x = torch::randn({8, 16, 104}), y = torch::rand({8, 16, 64 * 64});
  for (int k = 0; k < 8; ++k) {
    torch::manual_seed(100 + k);
    nchw.step(x[k], y[k], 1e-3);
    torch::manual_seed(100 + k);
    nhwc.step(x[k], y[k], 1e-3);
  }
  EXPECT_GT(relative_difference(start, detached(nchw_net->parameters())), 1e-3);
  const auto [nchw_images, nhwc_images] = images_of(nchw_net, nhwc_net, x[0]);
  EXPECT_LT(relative_difference({nchw_images}, {nhwc_images}), 1e-4);
  const double loss = nchw.loss_sum().item<double>();
  EXPECT_NEAR(nhwc.loss_sum().item<double>(), loss, 1e-5 * loss);
  // Back to NCHW: the same weights, in the standard layout, and the same function.
  nhwc_net->use_channels_last(false);
  for (const auto& p : nhwc_net->parameters()) EXPECT_TRUE(p.is_contiguous());
  torch::manual_seed(7);
  EXPECT_TRUE(torch::allclose(nhwc_net->forward(x[0]), nhwc_images, 1e-5, 1e-6));
}

}  // namespace
}  // namespace eitbench
