// `bumprad serve`: runs the HTTP render service (server/) with options from the command line;
// `bumprad worker`: a solver node on a shared PostgreSQL store, with the same options.
#pragma once

#include <span>
#include <string_view>

namespace bumprad {

int serve_command(std::span<const std::string_view> args);
int worker_command(std::span<const std::string_view> args);

}  // namespace bumprad
