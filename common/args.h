// One command-line parser for every bumprad tool (bumprad, bumprad-client, the benches):
// flags declared with where their value goes and its range, then parsed. Every value is read
// whole and checked; what is wrong is a UsageError that names the flag and says why. Values
// out of range are refused, never clamped.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace bumprad {

// A command line that cannot be run as given: the tool prints it with its usage and exits 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Whole numbers, exactly as written (optionally with a K, M or G suffix: 2^10, 2^20, 2^30),
// within [min, max]; numbers (decimal or scientific) within [min, max]. The errors name
// `flag`.
std::int64_t parse_integer(std::string_view flag, std::string_view text, std::int64_t min,
                           std::int64_t max, bool suffixes = false);
double parse_number(std::string_view flag, std::string_view text, double min, double max);

class ArgParser {
 public:
  // `names`: the flag and its aliases, e.g. {"-o", "--output"}. Each takes one value, given
  // as the next argument or after '='.
  ArgParser& text(std::vector<std::string> names, std::string& out);
  ArgParser& text(std::vector<std::string> names, std::optional<std::string>& out);
  ArgParser& integer(std::vector<std::string> names, std::int64_t& out, std::int64_t min,
                     std::int64_t max, bool suffixes = false);
  template <typename T>
  ArgParser& integer(std::vector<std::string> names, T& out, std::int64_t min, std::int64_t max,
                     bool suffixes = false) {
    return custom(std::move(names),
                  [&out, min, max, suffixes](std::string_view f, std::string_view v) {
                    out = static_cast<T>(parse_integer(f, v, min, max, suffixes));
                  });
  }
  template <typename T>
  ArgParser& integer(std::vector<std::string> names, std::optional<T>& out, std::int64_t min,
                     std::int64_t max, bool suffixes = false) {
    return custom(std::move(names),
                  [&out, min, max, suffixes](std::string_view f, std::string_view v) {
                    out = static_cast<T>(parse_integer(f, v, min, max, suffixes));
                  });
  }
  ArgParser& number(std::vector<std::string> names, double& out, double min, double max);
  ArgParser& number(std::vector<std::string> names, std::optional<double>& out, double min,
                    double max);
  // A flag with no value.
  ArgParser& toggle(std::vector<std::string> names, bool& out);
  // A flag whose value `read` converts (throwing UsageError for a bad one).
  ArgParser& custom(std::vector<std::string> names,
                    std::function<void(std::string_view flag, std::string_view value)> read);
  // Arguments that are not flags, in order: at most `max` of them.
  ArgParser& positional(std::vector<std::string>& out, std::size_t max = SIZE_MAX);

  // Reads `args` (without the program and command names). Throws UsageError.
  void parse(std::span<const std::string_view> args);
  void parse(int argc, const char* const* argv);  // argv[0] is the program
  // For a tool's main(): parses argv, or says "PROGRAM: what is wrong" and `usage` on stderr
  // and exits with status 2.
  void parse_or_exit(int argc, const char* const* argv, std::string_view usage);
  // Whether `flag` (any of its names counts as its first) was given.
  bool given(std::string_view flag) const;

 private:
  struct Flag {
    std::vector<std::string> names;
    bool takes_value;
    std::function<void(std::string_view, std::string_view)> read;
  };
  const Flag* find(std::string_view name) const;

  std::vector<Flag> flags_;
  std::vector<std::string>* positional_ = nullptr;
  std::size_t max_positional_ = 0;
  std::set<std::string, std::less<>> given_;
};

}  // namespace bumprad
