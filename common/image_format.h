// The image formats bumprad writes and serves, by name, extension and MIME type. Encoding
// itself needs the solver's Image and OpenImageIO (solver/util/image.h); this is what a client
// that only saves the server's bytes needs to know.
#pragma once

#include <filesystem>
#include <optional>
#include <string_view>

namespace bumprad {

// JPEG encodes several times faster than PNG: what interactive drafts are sent as.
enum class ImageFormat { Png, Exr, Jpeg };

// By extension (.png, .exr, .jpg or .jpeg, any case); nullopt for any other.
std::optional<ImageFormat> image_format_for(const std::filesystem::path& path);

// "png", "exr", "jpeg": the names requests use.
std::string_view format_name(ImageFormat format);
// "image/png", "image/x-exr", "image/jpeg".
std::string_view mime_type(ImageFormat format);

}  // namespace bumprad
