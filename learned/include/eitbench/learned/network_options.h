#pragma once
// The network's shape. Encoder: fully connected layers (Linear, BatchNorm, ReLU, dropout) from the
// frame to a C x s x s latent. Decoder: one stage per entry of decoder_channels (nearest 2x
// upsampling, 3x3 convolution, BatchNorm, ReLU), then a 3x3 convolution to one channel, masked to
// the disk. Upsampling + convolution instead of ConvTranspose2d: the latter has no oneDNN kernel in
// Debian's LibTorch 1.13 and trained 2-10x slower per FLOP here (BUILD-NOTES).
#include <string>
#include <vector>

namespace eitbench {

enum class ModelSize {
  small,  // sized for a 2-core CPU: ~1,000 training samples/s
  paper,  // the paper's widths (104 -> 512 -> 1024 -> 64 x 8 x 8); GPU advised
};
ModelSize parse_model_size(const std::string& name, const std::string& source = "--model");
std::string to_string(ModelSize size);

struct NetworkOptions {
  int inputs = 104;                             // frame length: L(L-3)/2, the reduced layout
  int image_size = 64;                          // output n x n = latent_size * 2^stages
  std::vector<int> hidden{256};                 // encoder widths before the latent
  int latent_channels = 32;                     // C
  int latent_size = 8;                          // s
  std::vector<int> decoder_channels{16, 8, 4};  // one upsampling stage each
  double dropout = 0.1;                         // after every hidden encoder layer
  double radius = 1.0;                          // the image spans [-R, R]^2; the disk mask

  // The widths of `size` for frames of `inputs` values and n x n images (n = 8 * 2^k).
  static NetworkOptions preset(ModelSize size, int inputs, int image_size);
};

// InputError(source, field, ...) when the shape is impossible (e.g. n != s * 2^stages).
void check_network_options(const NetworkOptions& options, const std::string& source);
// Multiply-adds x 2 of one forward pass for one sample (linear and convolution layers).
double forward_flops(const NetworkOptions& options);

}  // namespace eitbench
