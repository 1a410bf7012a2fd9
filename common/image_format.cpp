#include "common/image_format.h"

#include <algorithm>
#include <cctype>
#include <string>

namespace bumprad {

std::optional<ImageFormat> image_format_for(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".png") return ImageFormat::Png;
  if (ext == ".exr") return ImageFormat::Exr;
  if (ext == ".jpg" || ext == ".jpeg") return ImageFormat::Jpeg;
  return std::nullopt;
}

std::string_view format_name(ImageFormat format) {
  return format == ImageFormat::Png ? "png" : format == ImageFormat::Exr ? "exr" : "jpeg";
}

std::string_view mime_type(ImageFormat format) {
  switch (format) {
    case ImageFormat::Png:
      return "image/png";
    case ImageFormat::Exr:
      return "image/x-exr";
    case ImageFormat::Jpeg:
      return "image/jpeg";
  }
  return "application/octet-stream";
}

}  // namespace bumprad
