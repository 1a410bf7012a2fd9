#include "protocol/json_parse.h"

#include <cctype>

#include <nlohmann/json.hpp>

namespace bumprad {
namespace {

using json = nlohmann::json;

// Where the parser stopped at a value it did not expect ("unexpected string literal;
// expected '}'"), the usual cause is a missing comma after the value before it: that value's
// last byte (1-based, as the parser counts), or 0 when the text does not look so.
std::size_t missing_comma(std::string_view text, std::size_t byte, const std::string& why) {
  const bool value_came = why.find("unexpected string literal") != std::string::npos ||
                          why.find("unexpected number literal") != std::string::npos ||
                          why.find("unexpected '{'") != std::string::npos ||
                          why.find("unexpected '['") != std::string::npos ||
                          why.find("unexpected true literal") != std::string::npos ||
                          why.find("unexpected false literal") != std::string::npos ||
                          why.find("unexpected null literal") != std::string::npos;
  const bool end_expected = why.find("expected '}'") != std::string::npos ||
                            why.find("expected ']'") != std::string::npos;
  if (!value_came || !end_expected || byte == 0 || byte > text.size()) return 0;
  // Back over the unexpected token (a string from its closing quote to its opening one)...
  std::size_t at = byte - 1;
  if (text[at] == '"') {
    while (at > 0 && !(text[at - 1] == '"' && (at < 2 || text[at - 2] != '\\'))) --at;
    if (at == 0) return 0;
    --at;
  } else if (text[at] != '{' && text[at] != '[') {
    auto in_literal = [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+';
    };
    while (at > 0 && in_literal(text[at - 1])) --at;
  }
  // ...and the space before it, to the value that needed a comma after it.
  while (at > 0 && std::isspace(static_cast<unsigned char>(text[at - 1]))) --at;
  return at;
}

}  // namespace

json parse_json(std::string_view text) {
  // The parser itself keeps its own stack; this callback stops it at the first array or
  // object too deep, so no deeply nested value is ever built.
  auto depth_limit = [](int depth, json::parse_event_t event, json&) {
    if ((event == json::parse_event_t::object_start || event == json::parse_event_t::array_start) &&
        depth >= kMaxJsonDepth)
      throw MalformedJson("JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                          " arrays and objects");
    return true;
  };
  try {
    return json::parse(text, depth_limit);
  } catch (const json::parse_error& e) {
    const std::string what = e.what(), why = what.substr(what.find(':') + 2);
    if (const std::size_t comma = missing_comma(text, e.byte, why))
      throw MalformedJson("malformed JSON at byte " + std::to_string(comma) +
                          ": a comma is missing after this value (the parser, at byte " +
                          std::to_string(e.byte) + ": " + why + ")");
    throw MalformedJson("malformed JSON at byte " + std::to_string(e.byte) + ": " + why);
  } catch (const json::exception& e) {  // e.g. a number literal beyond double's range
    std::string what = e.what();
    throw MalformedJson("malformed JSON: " + what.substr(what.find(']') + 2));
  }
}

}  // namespace bumprad
