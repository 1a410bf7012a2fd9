// The files the server serves as they are: the web viewer (server/web/) and the OpenAPI
// description (protocol/openapi.json), compiled in so the binary is whole.
#pragma once

#include <span>
#include <string_view>

namespace bumprad {

struct WebAsset {
  std::string_view path;  // URL path: "/", "/viewer.js", "/v1/openapi"
  std::string_view content_type;
  std::string_view body;
};

std::span<const WebAsset> web_assets();

}  // namespace bumprad
