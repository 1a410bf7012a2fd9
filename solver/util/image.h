// Linear RGB images and their files: PNG (exposure, sRGB, 8-bit) for viewing and OpenEXR
// (linear radiance, half float) for HDR, both through OpenImageIO, both written atomically.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/image_format.h"
#include "solver/util/math.h"

namespace bumprad {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // row-major from the top-left, linear radiance

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(std::size_t(w) * std::size_t(h) * 3, 0.f) {}
  Rgb at(int x, int y) const;
  void set(int x, int y, const Rgb& c);
};

// The mean of its pixels.
Rgb image_mean(const Image& image);

// Linear [0,1] to the sRGB transfer curve.
double srgb_encode(double linear);

// The file's bytes: PNG and JPEG (quality 90) apply `exposure` and the sRGB curve; EXR keeps
// linear radiance and ignores exposure. Files and HTTP bodies share this one encoder.
std::string encode_image(const Image& image, ImageFormat format, double exposure);
// A 16-bit PNG of values that are data, not colours (heights, normals): as stored, clamped to
// [0, 1], with no exposure and no sRGB curve; read back with PixelMeaning::Data.
std::string encode_data_png(const Image& image);

// The format follows the extension (.png, .exr, .jpg); other extensions are refused.
// Throws std::runtime_error naming the path on failure.
void write_image(const std::filesystem::path& path, const Image& image, double exposure);

// What a file's 8-bit pixels hold: colours, stored on the sRGB curve, or data (heights,
// normals), stored as they are: 8-bit v reads as v / 255. Float formats are linear either way.
enum class PixelMeaning { Color, Data };

// What decoding may take while one request's images are read: every image is checked from
// its file's header, before a pixel is decoded, against a pixel limit and against what the
// images decoded before it have left of a byte budget. An image costs its linear floats
// (12 bytes a pixel, kept) and, while it decodes, the decoder's buffer of the file's own
// pixels (channels x bytes a channel); the budget holds the peak of both. A zero limit is none.
class ImageBudget {
 public:
  ImageBudget() = default;
  ImageBudget(std::size_t max_pixels, std::size_t max_bytes)
      : max_pixels_(max_pixels), max_bytes_(max_bytes) {}

  // Books an image of this shape, or throws std::runtime_error naming `name` and the limit
  // it would pass.
  void admit(const std::string& name, int width, int height, int channels,
             std::size_t bytes_per_channel);
  std::size_t taken() const { return taken_; }  // bytes the admitted images keep

 private:
  std::size_t max_pixels_ = 0, max_bytes_ = 0, taken_ = 0;
};

// Reads any format OpenImageIO knows into linear floats: the first three channels, or the
// first repeated when there are fewer (grey, grey + alpha). With a budget, the header is
// checked against it first.
Image read_image(const std::filesystem::path& path, ImageBudget* budget = nullptr,
                 PixelMeaning meaning = PixelMeaning::Color);
// The same from a file's bytes in memory (a model's embedded texture); `name` (with the
// format's extension, e.g. "texture.png") names it in errors.
Image decode_image(std::string_view bytes, const std::string& name, ImageBudget* budget = nullptr,
                   PixelMeaning meaning = PixelMeaning::Color);

}  // namespace bumprad
