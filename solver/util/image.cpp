#include "solver/util/image.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include "common/atomic_file.h"

namespace bumprad {

Rgb Image::at(int x, int y) const {
  std::size_t i = 3 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

void Image::set(int x, int y, const Rgb& c) {
  std::size_t i = 3 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
  rgb[i] = float(c.r);
  rgb[i + 1] = float(c.g);
  rgb[i + 2] = float(c.b);
}

Rgb image_mean(const Image& image) {
  Rgb sum(0);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) sum += image.at(x, y);
  return sum / double(std::max(1, image.width * image.height));
}

double srgb_encode(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055;
}

std::string encode_image(const Image& image, ImageFormat format, double exposure) {
  const std::string name(format_name(format));
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  auto out = OIIO::ImageOutput::create(name);
  if (!out) throw std::runtime_error("no " + name + " writer: " + OIIO::geterror());
  out->set_ioproxy(&proxy);
  bool ok;
  if (format != ImageFormat::Exr) {
    std::vector<std::uint8_t> px(image.rgb.size());
    for (std::size_t i = 0; i < px.size(); ++i)
      px[i] = std::uint8_t(std::lround(255 * srgb_encode(exposure * image.rgb[i])));
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    if (format == ImageFormat::Jpeg) spec.attribute("CompressionQuality", 90);
    ok = out->open("memory." + name, spec) && out->write_image(OIIO::TypeDesc::UINT8, px.data());
  } else {
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::HALF);
    ok = out->open("memory." + name, spec) &&
         out->write_image(OIIO::TypeDesc::FLOAT, image.rgb.data());
  }
  ok = out->close() && ok;
  if (!ok) throw std::runtime_error("encoding " + name + ": " + out->geterror());
  return std::string(bytes.begin(), bytes.end());
}

void write_image(const std::filesystem::path& path, const Image& image, double exposure) {
  auto format = image_format_for(path);
  if (!format)
    throw std::runtime_error(path.string() + ": unsupported image type (use .png, .exr or .jpg)");
  write_file_atomically(path, encode_image(image, *format, exposure));
}

namespace {

// Decodes what `in` opened, named `name` in errors, after its header's size is checked.
Image decode(OIIO::ImageInput* in, const std::string& name, std::size_t max_pixels,
             PixelMeaning meaning) {
  if (!in) throw std::runtime_error(name + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  const std::size_t pixels = std::size_t(spec.width) * std::size_t(spec.height);
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw std::runtime_error(name + ": the image has no pixels");
  if (max_pixels > 0 && pixels > max_pixels)
    throw std::runtime_error(name + ": " + std::to_string(spec.width) + " x " +
                             std::to_string(spec.height) + " pixels, over the limit of " +
                             std::to_string(max_pixels));
  std::vector<float> px(pixels * std::size_t(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()))
    throw std::runtime_error(name + ": " + in->geterror());
  // Integer pixels (8- and 16-bit PNG, JPEG) hold colours on the sRGB curve unless the file
  // says it is linear (a PNG's gAMA of 1.0); floats are linear.
  const std::string space = spec.get_string_attribute("oiio:ColorSpace");
  const bool srgb = meaning == PixelMeaning::Color && !spec.format.is_floating_point() &&
                    !OIIO::Strutil::istarts_with(space, "lin");
  Image img(spec.width, spec.height);
  for (std::size_t i = 0; i < pixels; ++i)
    for (std::size_t c = 0; c < 3; ++c) {
      float v = px[i * std::size_t(spec.nchannels) +
                   std::min<std::size_t>(c, std::size_t(spec.nchannels) - 1)];
      if (srgb) v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
      img.rgb[3 * i + c] = v;
    }
  return img;
}

}  // namespace

Image read_image(const std::filesystem::path& path, std::size_t max_pixels, PixelMeaning meaning) {
  auto in = OIIO::ImageInput::open(path.string());
  return decode(in.get(), path.string(), max_pixels, meaning);
}

Image decode_image(std::string_view bytes, const std::string& name, std::size_t max_pixels,
                   PixelMeaning meaning) {
  OIIO::Filesystem::IOMemReader reader(const_cast<char*>(bytes.data()), bytes.size());
  // OpenImageIO picks the reader by the name's extension; the bytes come through the proxy.
  auto in = OIIO::ImageInput::open(name, nullptr, &reader);
  return decode(in.get(), name, max_pixels, meaning);
}

}  // namespace bumprad
