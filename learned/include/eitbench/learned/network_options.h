#pragma once
// The network's shape. Encoder: fully connected layers (Linear, BatchNorm, ReLU, dropout) from the
// frame to a C x s x s latent. Decoder, in one of two forms:
//  - pixel_shuffle (sub-pixel convolution): one stage per entry c of decoder_channels (3x3
//    convolution to 4c channels at the current size, pixel shuffle to c channels at twice the size,
//    BatchNorm, ReLU), then an output stage (3x3 convolution to 4 channels, pixel shuffle to the
//    image). Every convolution runs at half the size it produces, so it trains several times faster
//    than `nearest` on a CPU (oneDNN's backward pass is slow on few channels at large sizes;
//    docs/learned.md has the measurements).
//  - nearest: one stage per entry (nearest 2x upsampling, 3x3 convolution, BatchNorm, ReLU), then a
//    3x3 convolution to one channel at full size; the form of models made before pixel_shuffle.
// Either is masked to the disk. Neither uses ConvTranspose2d: it has no oneDNN kernel in Debian's
// LibTorch 1.13 and trained several times slower per FLOP (docs/learned.md).
#include <string>
#include <vector>

namespace eitbench {

enum class ModelSize {
  small,  // sized for a 2-core CPU (its training speed: docs/learned.md)
  paper,  // the paper's widths (104 -> 512 -> 1024 -> 64 x 8 x 8); GPU advised
};
ModelSize parse_model_size(const std::string& name, const std::string& source = "ModelSize");
std::string to_string(ModelSize size);

enum class Upsampling { pixel_shuffle, nearest };
Upsampling parse_upsampling(const std::string& name, const std::string& source);
std::string to_string(Upsampling upsampling);

// Every count and width positive.
struct NetworkOptions {
  int inputs = 104;                          // frame length: L(L-3)/2, the reduced layout
  int image_size = 64;                       // output n x n = latent_size * 2^upsampling_stages()
  std::vector<int> hidden{256};              // encoder widths before the latent
  int latent_channels = 32;                  // C
  int latent_size = 8;                       // s
  std::vector<int> decoder_channels{16, 8};  // one upsampling stage each, at most 8
  Upsampling upsampling = Upsampling::pixel_shuffle;
  double dropout = 0.1;  // after every hidden encoder layer, in [0, 1)
  double radius = 1.0;   // the image spans [-R, R]^2; the disk mask. Positive and finite
  // A sensor of another shape: its grid's mask (image_size^2, true inside; PixelGrid::covering),
  // which replaces the disk's. Kept in the model file as the network's mask buffer, not here.
  std::vector<bool> mask;

  // Throws InputError("NetworkOptions", field) when the shape is impossible (as
  // check_network_options).
  void validate() const;

  // The widths of `size` for frames of `inputs` values and n x n images (n = 8 * 2^k).
  static NetworkOptions preset(ModelSize size, int inputs, int image_size);
  // 2x stages from the latent to the image: one per decoder channel, plus the output stage of
  // pixel_shuffle.
  int upsampling_stages() const;
};

// InputError(source, field, ...) when the shape is impossible (e.g. n != s * 2^stages): source
// names where the options came from (a model file's path, or "NetworkOptions").
void check_network_options(const NetworkOptions& options, const std::string& source);
// Multiply-adds x 2 of one forward pass for one sample (linear and convolution layers).
double forward_flops(const NetworkOptions& options);

}  // namespace eitbench
