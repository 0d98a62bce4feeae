#include <cmath>

#include "eitbench/jacobian/error.h"
#include "eitbench/learned/network_options.h"

namespace eitbench {

ModelSize parse_model_size(const std::string& name, const std::string& source) {
  if (name == "small") return ModelSize::small;
  if (name == "paper") return ModelSize::paper;
  throw InputError(source, "", "unknown model '" + name + "' (small or paper)");
}

std::string to_string(ModelSize size) {
  return size == ModelSize::small ? "small" : "paper";
}

Upsampling parse_upsampling(const std::string& name, const std::string& source) {
  if (name == "pixel_shuffle") return Upsampling::pixel_shuffle;
  if (name == "nearest") return Upsampling::nearest;
  throw InputError(source, "upsampling",
                   "unknown upsampling '" + name + "' (pixel_shuffle or nearest)");
}

std::string to_string(Upsampling upsampling) {
  return upsampling == Upsampling::pixel_shuffle ? "pixel_shuffle" : "nearest";
}

int NetworkOptions::upsampling_stages() const {
  return static_cast<int>(decoder_channels.size()) + (upsampling == Upsampling::pixel_shuffle);
}

NetworkOptions NetworkOptions::preset(ModelSize size, int inputs, int image_size) {
  NetworkOptions o;
  o.inputs = inputs;
  o.image_size = image_size;
  o.latent_size = image_size / 8;  // three 2x stages: two decoder stages and the output's
  if (size == ModelSize::paper) {
    o.hidden = {512, 1024};
    o.latent_channels = 64;
    o.decoder_channels = {32, 16};
    o.dropout = 0.2;
  }
  return o;
}

void check_network_options(const NetworkOptions& o, const std::string& source) {
  auto positive = [&](int v, const std::string& field) {
    if (v <= 0) throw InputError(source, field, "must be positive, not " + std::to_string(v));
  };
  positive(o.inputs, "inputs");
  positive(o.image_size, "image_size");
  positive(o.latent_channels, "latent_channels");
  positive(o.latent_size, "latent_size");
  for (int w : o.hidden) positive(w, "hidden");
  for (int c : o.decoder_channels) positive(c, "decoder_channels");
  if (o.decoder_channels.size() > 8)
    throw InputError(source, "decoder_channels", "too many stages");
  const long long n = static_cast<long long>(o.latent_size) << o.upsampling_stages();
  if (n != o.image_size)
    throw InputError(source, "image_size",
                     std::to_string(o.image_size) + " is not latent_size * 2^" +
                         std::to_string(o.upsampling_stages()) + " = " + std::to_string(n) + " (" +
                         to_string(o.upsampling) + " upsampling)");
  if (!(o.dropout >= 0 && o.dropout < 1)) throw InputError(source, "dropout", "must lie in [0, 1)");
  if (!(o.radius > 0) || !std::isfinite(o.radius))
    throw InputError(source, "radius", "must be positive");
  if (!o.mask.empty() && o.mask.size() != static_cast<std::size_t>(o.image_size) *
                                              static_cast<std::size_t>(o.image_size))
    throw InputError(source, "mask", "must have image_size^2 values, one a pixel");
}

void NetworkOptions::validate() const {
  check_network_options(*this, "NetworkOptions");
}

double forward_flops(const NetworkOptions& o) {
  double macs = 0;
  int width = o.inputs;
  for (int h : o.hidden) macs += double(width) * h, width = h;
  macs += double(width) * o.latent_channels * o.latent_size * o.latent_size;
  // A 3x3 convolution from c to c' channels producing a side x side image costs 9 c c' side^2
  // multiply-adds, whether it runs at full size (nearest) or at half size to 4c' (pixel_shuffle).
  int channels = o.latent_channels, side = o.latent_size;
  for (int c : o.decoder_channels) {
    side *= 2;
    macs += 9.0 * channels * c * side * side;
    channels = c;
  }
  if (o.upsampling == Upsampling::pixel_shuffle) side *= 2;
  macs += 9.0 * channels * side * side;
  return 2 * macs;
}

}  // namespace eitbench
