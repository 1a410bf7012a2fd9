// Base64 (RFC 4648, with padding): how files travel inside a scene's JSON ("files") and so
// inside stored jobs and saved solutions.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace bumprad {

std::string base64_encode(std::string_view bytes);

// The bytes, or nullopt when `text` is not base64 (a wrong character, length or padding).
std::optional<std::string> base64_decode(std::string_view text);

}  // namespace bumprad
