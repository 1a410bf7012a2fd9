#include "cli/command.h"

#include <iostream>

#include "common/args.h"

namespace bumprad {

int run_command(std::string_view name, std::string_view usage,
                std::span<const std::string_view> args,
                const std::function<int(std::span<const std::string_view>)>& body) {
  if (args.size() == 1 && (args[0] == "--help" || args[0] == "-h")) {
    std::cout << usage;
    return 0;
  }
  try {
    return body(args);
  } catch (const UsageError& e) {
    std::cerr << "bumprad " << name << ": " << e.what() << "\n" << usage;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "bumprad: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace bumprad
