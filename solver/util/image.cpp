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

std::string encode_data_png(const Image& image) {
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  auto out = OIIO::ImageOutput::create("png");
  if (!out) throw std::runtime_error("no png writer: " + OIIO::geterror());
  out->set_ioproxy(&proxy);
  std::vector<std::uint16_t> px(image.rgb.size());
  for (std::size_t i = 0; i < px.size(); ++i)
    px[i] = std::uint16_t(std::lround(65535 * std::clamp(double(image.rgb[i]), 0.0, 1.0)));
  const OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT16);
  bool ok = out->open("memory.png", spec) && out->write_image(OIIO::TypeDesc::UINT16, px.data());
  ok = out->close() && ok;
  if (!ok) throw std::runtime_error("encoding png: " + out->geterror());
  return std::string(bytes.begin(), bytes.end());
}

void write_image(const std::filesystem::path& path, const Image& image, double exposure) {
  auto format = image_format_for(path);
  if (!format)
    throw std::runtime_error(path.string() + ": unsupported image type (use .png, .exr or .jpg)");
  write_file_atomically(path, encode_image(image, *format, exposure));
}

namespace {

// Rounded up, so that what is refused never reads as fitting.
std::string describe_bytes(std::size_t bytes) {
  return bytes < 1'000'000 ? std::to_string((bytes + 999) / 1000) + " KB"
                           : std::to_string((bytes + 999'999) / 1'000'000) + " MB";
}

}  // namespace

void ImageBudget::admit(const std::string& name, int width, int height, int channels,
                        std::size_t bytes_per_channel) {
  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  if (max_pixels_ > 0 && pixels > max_pixels_)
    throw std::runtime_error(name + ": " + std::to_string(width) + " x " + std::to_string(height) +
                             " pixels, over the limit of " + std::to_string(max_pixels_));
  const std::size_t kept = pixels * 3 * sizeof(float);
  const std::size_t peak = kept + pixels * std::size_t(channels) * bytes_per_channel;
  if (max_bytes_ > 0 && taken_ + peak > max_bytes_)
    throw std::runtime_error(
        name + ": " + std::to_string(width) + " x " + std::to_string(height) + " pixels take " +
        describe_bytes(peak) + " to decode, over what is left of the " +
        describe_bytes(max_bytes_) + " one scene's images may take" +
        (taken_ > 0 ? " (" + describe_bytes(taken_) + " taken by the images before it)" : ""));
  taken_ += kept;
}

namespace {

// Decodes what `in` opened, named `name` in errors, after its header is admitted.
Image decode(OIIO::ImageInput* in, const std::string& name, ImageBudget* budget,
             PixelMeaning meaning) {
  if (!in) throw std::runtime_error(name + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw std::runtime_error(name + ": the image has no pixels");
  if (budget) budget->admit(name, spec.width, spec.height, spec.nchannels, spec.format.size());
  // Straight into the image's own floats, three to a pixel: no second copy of the pixels.
  Image img(spec.width, spec.height);
  const int channels = spec.nchannels >= 3 ? 3 : 1;
  constexpr OIIO::stride_t kPixel = 3 * sizeof(float);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, img.rgb.data(), kPixel))
    throw std::runtime_error(name + ": " + in->geterror());
  // Integer pixels (8- and 16-bit PNG, JPEG) hold colours on the sRGB curve unless the file
  // says it is linear (a PNG's gAMA of 1.0); floats are linear.
  const std::string space = spec.get_string_attribute("oiio:ColorSpace");
  const bool srgb = meaning == PixelMeaning::Color && !spec.format.is_floating_point() &&
                    !OIIO::Strutil::istarts_with(space, "lin");
  for (std::size_t i = 0; i < img.rgb.size(); i += 3)
    for (std::size_t c = 0; c < 3; ++c) {
      float& v = img.rgb[i + c];
      if (c >= std::size_t(channels))
        v = img.rgb[i];  // grey: one value for all three
      else if (srgb)
        v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
    }
  return img;
}

// OpenImageIO multiplies colours by alpha as it reads unless told not to; bumprad's images
// are reflectances, heights and normals, which alpha must not scale.
const OIIO::ImageSpec& as_stored() {
  static const OIIO::ImageSpec config = [] {
    OIIO::ImageSpec c;
    c.attribute("oiio:UnassociatedAlpha", 1);
    return c;
  }();
  return config;
}

}  // namespace

Image read_image(const std::filesystem::path& path, ImageBudget* budget, PixelMeaning meaning) {
  auto in = OIIO::ImageInput::open(path.string(), &as_stored());
  return decode(in.get(), path.string(), budget, meaning);
}

Image decode_image(std::string_view bytes, const std::string& name, ImageBudget* budget,
                   PixelMeaning meaning) {
  OIIO::Filesystem::IOMemReader reader(const_cast<char*>(bytes.data()), bytes.size());
  // OpenImageIO picks the reader by the name's extension; the bytes come through the proxy.
  // With a configuration, OpenImageIO 2.4 takes the proxy from it, not from the argument.
  OIIO::ImageSpec config = as_stored();
  void* proxy = &reader;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  auto in = OIIO::ImageInput::open(name, &config, &reader);
  return decode(in.get(), name, budget, meaning);
}

}  // namespace bumprad
