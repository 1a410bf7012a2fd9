// `bumprad serve`: runs the HTTP render service (server/) with options from the command line.
#pragma once

#include <span>
#include <string_view>

namespace bumprad {

int serve_command(std::span<const std::string_view> args);

}  // namespace bumprad
