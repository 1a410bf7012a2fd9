#include "protocol/json_parse.h"

#include <nlohmann/json.hpp>

namespace bumprad {

using json = nlohmann::json;

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
    throw MalformedJson("malformed JSON at byte " + std::to_string(e.byte) + ": " +
                        std::string(e.what()).substr(std::string(e.what()).find(':') + 2));
  } catch (const json::exception& e) {  // e.g. a number literal beyond double's range
    std::string what = e.what();
    throw MalformedJson("malformed JSON: " + what.substr(what.find(']') + 2));
  }
}

}  // namespace bumprad
