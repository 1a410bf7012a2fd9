// Linear RGB images and their files: PNG (exposure, sRGB, 8-bit) for viewing and OpenEXR
// (linear radiance, half float) for HDR, both through OpenImageIO, both written atomically.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "solver/math.h"

namespace bumprad {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // row-major from the top-left, linear radiance

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(std::size_t(w) * std::size_t(h) * 3, 0.f) {}
  Rgb at(int x, int y) const;
  void set(int x, int y, const Rgb& c);
};

// Linear [0,1] to the sRGB transfer curve.
double srgb_encode(double linear);

enum class ImageFormat { Png, Exr };

// By extension (.png or .exr, any case); nullopt for any other.
std::optional<ImageFormat> image_format_for(const std::filesystem::path& path);

// The file's bytes: PNG applies `exposure` and the sRGB curve; EXR keeps linear radiance
// and ignores exposure. Files and HTTP bodies share this one encoder.
std::string encode_image(const Image& image, ImageFormat format, double exposure);

// The format follows the extension (.png or .exr); other extensions are refused.
// Throws std::runtime_error naming the path on failure.
void write_image(const std::filesystem::path& path, const Image& image, double exposure);

// Reads any format OpenImageIO knows into linear floats (PNG is decoded from sRGB).
Image read_image(const std::filesystem::path& path);

}  // namespace bumprad
