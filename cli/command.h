// How every `bumprad` command runs: --help prints its usage; a UsageError from its body is
// printed with the usage (exit 2), any other error as "bumprad: error: ..." (exit 1).
#pragma once

#include <functional>
#include <span>
#include <string_view>

namespace bumprad {

int run_command(std::string_view name, std::string_view usage,
                std::span<const std::string_view> args,
                const std::function<int(std::span<const std::string_view>)>& body);

}  // namespace bumprad
