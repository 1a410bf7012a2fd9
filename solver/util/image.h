// Linear RGB images and their files: PNG (exposure, sRGB, 8-bit) for viewing and OpenEXR
// (linear radiance, half float) for HDR, both through OpenImageIO, both written atomically.
#pragma once

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

// The format follows the extension (.png, .exr, .jpg); other extensions are refused.
// Throws std::runtime_error naming the path on failure.
void write_image(const std::filesystem::path& path, const Image& image, double exposure);

// What a file's 8-bit pixels hold: colours, stored on the sRGB curve, or data (heights,
// normals), stored as they are: 8-bit v reads as v / 255. Float formats are linear either way.
enum class PixelMeaning { Color, Data };

// Reads any format OpenImageIO knows into linear floats. With `max_pixels`, an image whose
// header says it is larger is refused before it is decoded.
Image read_image(const std::filesystem::path& path, std::size_t max_pixels = 0,
                 PixelMeaning meaning = PixelMeaning::Color);
// The same from a file's bytes in memory (a model's embedded texture); `name` (with the
// format's extension, e.g. "texture.png") names it in errors.
Image decode_image(std::string_view bytes, const std::string& name, std::size_t max_pixels = 0,
                   PixelMeaning meaning = PixelMeaning::Color);

}  // namespace bumprad
