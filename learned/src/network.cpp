#include "network.h"

#include <nlohmann/json.hpp>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/pixel_grid.h"

namespace eitbench {

NetworkImpl::NetworkImpl(const NetworkOptions& o) : options(o) {
  o.validate();
  namespace nn = torch::nn;
  nn::Sequential enc;
  int width = o.inputs;
  for (int h : o.hidden) {
    enc->push_back(nn::Linear(width, h));
    enc->push_back(nn::BatchNorm1d(h));
    enc->push_back(nn::ReLU());
    if (o.dropout > 0) enc->push_back(nn::Dropout(o.dropout));
    width = h;
  }
  const int latent = o.latent_channels * o.latent_size * o.latent_size;
  enc->push_back(nn::Linear(width, latent));
  enc->push_back(nn::BatchNorm1d(latent));
  enc->push_back(nn::ReLU());
  encoder = register_module("encoder", enc);

  nn::Sequential dec;
  int channels = o.latent_channels;
  const bool shuffle = o.upsampling == Upsampling::pixel_shuffle;
  for (int c : o.decoder_channels) {
    if (shuffle) {
      dec->push_back(nn::Conv2d(nn::Conv2dOptions(channels, 4 * c, 3).padding(1).bias(false)));
      dec->push_back(nn::PixelShuffle(2));
    } else {
      dec->push_back(nn::Upsample(
          nn::UpsampleOptions().scale_factor(std::vector<double>{2, 2}).mode(torch::kNearest)));
      dec->push_back(nn::Conv2d(nn::Conv2dOptions(channels, c, 3).padding(1).bias(false)));
    }
    dec->push_back(nn::BatchNorm2d(c));
    dec->push_back(nn::ReLU());
    channels = c;
  }
  if (shuffle) {
    dec->push_back(nn::Conv2d(nn::Conv2dOptions(channels, 4, 3).padding(1)));
    dec->push_back(nn::PixelShuffle(2));
  } else {
    dec->push_back(nn::Conv2d(nn::Conv2dOptions(channels, 1, 3).padding(1)));
  }
  decoder = register_module("decoder", dec);

  mean = register_buffer("input_mean", torch::zeros({o.inputs}));
  scale = register_buffer("input_scale", torch::ones({o.inputs}));
  // The disk as the rest of eitbench draws it (PixelGrid: pixel centres inside the rim).
  // A sensor of another shape brings its own.
  const PixelGrid grid(o.image_size, o.radius);
  const auto& inside = grid.mask();
  auto m = torch::zeros({static_cast<long>(inside.size())});
  auto a = m.accessor<float, 1>();
  for (Eigen::Index p = 0; p < inside.size(); ++p)
    a[p] = (o.mask.empty() ? inside[p] : o.mask[static_cast<std::size_t>(p)]) ? 1.0f : 0.0f;
  mask = register_buffer("disk_mask", m);
}

torch::Tensor NetworkImpl::forward(const torch::Tensor& frames) {
  const auto x = (frames - mean) * scale;
  auto image = encoder->forward(x).view(
      {-1, options.latent_channels, options.latent_size, options.latent_size});
  if (!channels_last_) {
    image = decoder->forward(image);
  } else {
    image = image.contiguous(torch::MemoryFormat::ChannelsLast);
    for (auto& layer : *decoder) {
      if (auto* shuffle = layer.ptr()->as<torch::nn::PixelShuffle>())
        image = pixel_shuffle_keeping_layout(image,
                                             static_cast<int>(shuffle->options.upscale_factor()));
      else
        image = layer.forward(image);
    }
  }
  // reshape: a one-channel image is laid out alike in NCHW and NHWC, so it is a view either way.
  return image.reshape({-1, options.image_size * options.image_size}) * mask;
}

void NetworkImpl::use_channels_last(bool on) {
  torch::NoGradGuard no_grad;
  const auto layout = on ? torch::MemoryFormat::ChannelsLast : torch::MemoryFormat::Contiguous;
  for (auto& p : decoder->parameters())
    if (p.dim() == 4) p.set_data(p.data().contiguous(layout));
  channels_last_ = on;
}

torch::Tensor pixel_shuffle_keeping_layout(const torch::Tensor& x, int factor) {
  if (x.dim() != 4 || x.is_contiguous() || !x.is_contiguous(torch::MemoryFormat::ChannelsLast))
    return torch::pixel_shuffle(x, factor);
  const long n = x.size(0), c = x.size(1), h = x.size(2), w = x.size(3), r = factor;
  if (c % (r * r) != 0) return torch::pixel_shuffle(x, factor);  // its message for the error
  // In memory x is [n, h, w, c] with c = (oc, i, j); the output pixel (h r + i, w r + j) of
  // channel oc is that element, so the output's memory [n, h, i, w, j, oc] is one permuted copy.
  const long oc = c / (r * r);
  return x.permute({0, 2, 3, 1})
      .view({n, h, w, oc, r, r})
      .permute({0, 1, 4, 2, 5, 3})
      .contiguous()
      .view({n, h * r, w * r, oc})
      .permute({0, 3, 1, 2});
}

void copy_state(const Network& from, Network& to) {
  torch::NoGradGuard no_grad;
  const auto source = from->named_parameters(true), target = to->named_parameters(true);
  for (const auto& p : source) target[p.key()].copy_(p.value());
  const auto sb = from->named_buffers(true), tb = to->named_buffers(true);
  for (const auto& b : sb) tb[b.key()].copy_(b.value());
}

torch::Tensor to_tensor(const SampleMatrix& rows, const torch::Device& device) {
  auto t = torch::from_blob(const_cast<double*>(rows.data()), {rows.rows(), rows.cols()},
                            torch::kFloat64)
               .to(torch::kFloat32);
  return device.is_cpu() ? t : t.to(device);
}

SampleMatrix to_samples(const torch::Tensor& tensor) {
  const auto t = tensor.to(torch::kCPU).to(torch::kFloat64).contiguous();
  SampleMatrix out(t.size(0), t.size(1));
  std::copy(t.data_ptr<double>(), t.data_ptr<double>() + t.numel(), out.data());
  return out;
}

std::string first_line(const c10::Error& error) {
  const std::string what = error.what_without_backtrace();
  return what.substr(0, what.find('\n'));
}

std::string first_line(const std::exception& error) {
  const std::string what = error.what();
  return what.substr(0, what.find('\n'));
}

std::string network_to_json(const NetworkOptions& o) {
  nlohmann::json j = {{"inputs", o.inputs},
                      {"image_size", o.image_size},
                      {"hidden", o.hidden},
                      {"latent_channels", o.latent_channels},
                      {"latent_size", o.latent_size},
                      {"decoder_channels", o.decoder_channels},
                      {"dropout", o.dropout},
                      {"radius", o.radius},
                      {"upsampling", to_string(o.upsampling)}};
  return j.dump();
}

NetworkOptions network_from_json(const std::string& text, const std::string& source) {
  NetworkOptions o;
  try {
    const auto j = nlohmann::json::parse(text);
    o.inputs = j.at("inputs").get<int>();
    o.image_size = j.at("image_size").get<int>();
    o.hidden = j.at("hidden").get<std::vector<int>>();
    o.latent_channels = j.at("latent_channels").get<int>();
    o.latent_size = j.at("latent_size").get<int>();
    o.decoder_channels = j.at("decoder_channels").get<std::vector<int>>();
    o.dropout = j.at("dropout").get<double>();
    o.radius = j.at("radius").get<double>();
    // Models written before the field existed have the nearest-upsampling decoder.
    o.upsampling = parse_upsampling(j.value("upsampling", std::string("nearest")), source);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, "network", std::string("not a network description: ") + e.what());
  }
  check_network_options(o, source);
  return o;
}

}  // namespace eitbench
