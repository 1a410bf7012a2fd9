// Runs one of our programs the way a user would, through the shell, and keeps what it said.
#pragma once

#include <string>

namespace bumprad::test {

struct CommandResult {
  int exit_code;
  std::string output;  // stdout and stderr together
};

// `command_line` is passed to /bin/sh with stderr joined to stdout.
CommandResult run_command(const std::string& command_line);

}  // namespace bumprad::test
