// Reading JSON that comes from outside: a parser that refuses deep nesting, and the errors
// every reader throws, each naming the offending field as a JSON pointer and saying why.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

namespace bumprad {

class SceneError : public std::runtime_error {
 public:
  SceneError(std::string pointer, const std::string& reason)
      : std::runtime_error((pointer.empty() ? std::string("/") : pointer) + ": " + reason),
        pointer_(std::move(pointer)),
        reason_(reason) {}
  // RFC 6901 pointer to the offending value; empty for the document itself.
  const std::string& pointer() const { return pointer_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string pointer_;
  std::string reason_;
};

// The text is not JSON at all (HTTP answers 400 for this, 422 for other SceneErrors).
class MalformedJson : public SceneError {
 public:
  explicit MalformedJson(const std::string& reason) : SceneError("", reason) {}
};

// Arrays and objects nest at most this deep in any JSON bumprad reads (a scene needs 5, a
// request 6): deeper documents are refused while parsing, before anything copies them, since
// copying, printing and freeing a JSON value recurse once per level.
constexpr int kMaxJsonDepth = 32;

// JSON text to a document; throws MalformedJson saying where and why, also for nesting
// deeper than kMaxJsonDepth.
nlohmann::json parse_json(std::string_view text);

}  // namespace bumprad
