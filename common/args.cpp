#include "common/args.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace bumprad {
namespace {

std::string quoted(std::string_view flag, std::string_view text) {
  return std::string(flag) + ": \"" + std::string(text) + "\"";
}

std::string number_text(double x) {
  std::string s = std::to_string(x);
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  return s;
}

}  // namespace

std::int64_t parse_integer(std::string_view flag, std::string_view text, std::int64_t min,
                           std::int64_t max, bool suffixes) {
  std::int64_t value = 0;
  const char* last = text.data() + text.size();
  auto [end, ec] = std::from_chars(text.data(), last, value);
  const std::string_view rest(end, std::size_t(last - end));
  const int shift = !suffixes || rest.empty() ? 0
                    : rest == "K"             ? 10
                    : rest == "M"             ? 20
                    : rest == "G"             ? 30
                                              : -1;
  const std::string range = " from " + std::to_string(min) + " to " + std::to_string(max);
  if (ec == std::errc::result_out_of_range)
    throw UsageError(quoted(flag, text) + " is out of range: give a whole number" + range);
  if (ec != std::errc() || shift < 0 || (!rest.empty() && shift == 0))
    throw UsageError(quoted(flag, text) + " is not a whole number" +
                     (suffixes ? " (with an optional K, M or G)" : ""));
  if (value > (std::numeric_limits<std::int64_t>::max() >> shift) ||
      value < (std::numeric_limits<std::int64_t>::min() >> shift) || (value << shift) < min ||
      (value << shift) > max)
    throw UsageError(quoted(flag, text) + " is out of range: give a whole number" + range);
  return value << shift;
}

double parse_number(std::string_view flag, std::string_view text, double min, double max) {
  double value = 0;
  const char* last = text.data() + text.size();
  auto [end, ec] = std::from_chars(text.data(), last, value);
  if (ec != std::errc() || end != last || !std::isfinite(value))
    throw UsageError(quoted(flag, text) + " is not a number");
  if (value < min || value > max)
    throw UsageError(quoted(flag, text) + " is out of range: give a number from " +
                     number_text(min) + " to " + number_text(max));
  return value;
}

ArgParser& ArgParser::custom(std::vector<std::string> names,
                             std::function<void(std::string_view, std::string_view)> read) {
  flags_.push_back({std::move(names), true, std::move(read)});
  return *this;
}

ArgParser& ArgParser::text(std::vector<std::string> names, std::string& out) {
  return custom(std::move(names), [&out](std::string_view, std::string_view v) { out = v; });
}

ArgParser& ArgParser::text(std::vector<std::string> names, std::optional<std::string>& out) {
  return custom(std::move(names), [&out](std::string_view, std::string_view v) { out = v; });
}

ArgParser& ArgParser::integer(std::vector<std::string> names, std::int64_t& out, std::int64_t min,
                              std::int64_t max, bool suffixes) {
  return integer<std::int64_t>(std::move(names), out, min, max, suffixes);
}

ArgParser& ArgParser::number(std::vector<std::string> names, double& out, double min, double max) {
  return custom(std::move(names), [&out, min, max](std::string_view f, std::string_view v) {
    out = parse_number(f, v, min, max);
  });
}

ArgParser& ArgParser::number(std::vector<std::string> names, std::optional<double>& out, double min,
                             double max) {
  return custom(std::move(names), [&out, min, max](std::string_view f, std::string_view v) {
    out = parse_number(f, v, min, max);
  });
}

ArgParser& ArgParser::toggle(std::vector<std::string> names, bool& out) {
  flags_.push_back(
      {std::move(names), false, [&out](std::string_view, std::string_view) { out = true; }});
  return *this;
}

ArgParser& ArgParser::positional(std::vector<std::string>& out, std::size_t max) {
  positional_ = &out;
  max_positional_ = max;
  return *this;
}

const ArgParser::Flag* ArgParser::find(std::string_view name) const {
  for (const Flag& f : flags_)
    for (const std::string& n : f.names)
      if (n == name) return &f;
  return nullptr;
}

void ArgParser::parse(std::span<const std::string_view> args) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string_view arg = args[i];
    if (!arg.starts_with("-") || arg == "-") {
      if (!positional_ || positional_->size() >= max_positional_)
        throw UsageError("unexpected argument \"" + std::string(arg) + "\"");
      positional_->emplace_back(arg);
      continue;
    }
    const std::size_t equals = arg.find('=');
    const std::string_view name = arg.substr(0, equals);
    const Flag* flag = find(name);
    if (!flag) throw UsageError("unknown option " + std::string(name));
    const std::string& canonical = flag->names.front();
    if (!flag->takes_value) {
      if (equals != std::string_view::npos) throw UsageError(std::string(name) + " takes no value");
      flag->read(name, {});
    } else if (equals != std::string_view::npos) {
      flag->read(name, arg.substr(equals + 1));
    } else {
      if (i + 1 >= args.size()) throw UsageError(std::string(name) + " needs a value");
      flag->read(name, args[++i]);
    }
    given_.insert(canonical);
  }
}

void ArgParser::parse(int argc, const char* const* argv) {
  std::vector<std::string_view> args(argv + 1, argv + argc);
  parse(args);
}

void ArgParser::parse_or_exit(int argc, const char* const* argv, std::string_view usage) {
  try {
    parse(argc, argv);
  } catch (const UsageError& e) {
    const std::string_view program = argc > 0 ? argv[0] : "";
    std::fprintf(stderr, "%s: %s\n%.*s",
                 std::string(program.substr(program.rfind('/') + 1)).c_str(), e.what(),
                 int(usage.size()), usage.data());
    std::exit(2);
  }
}

bool ArgParser::given(std::string_view flag) const {
  const Flag* f = find(flag);
  return f && given_.contains(f->names.front());
}

}  // namespace bumprad
