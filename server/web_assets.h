// The files the server serves as they are: the web viewer (server/web/) and the OpenAPI
// description (protocol/openapi.json), compiled in so the binary is whole.
#pragma once

#include <optional>
#include <string_view>

namespace bumprad {

struct WebAsset {
  std::string_view path;  // URL path: "/", "/viewer.js", "/v1/openapi"
  std::string_view content_type;
  std::string_view body;
};

std::optional<WebAsset> find_web_asset(std::string_view path);

}  // namespace bumprad
