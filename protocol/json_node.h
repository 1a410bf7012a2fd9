// A JSON value and where it sits in its document (an RFC 6901 pointer), with typed, checked
// accessors whose every rejection is a SceneError naming that place. The scene format and
// the HTTP API's requests are read through it.
#pragma once

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "protocol/json_parse.h"
#include "solver/scene/scene.h"  // Vec3, Rgb and Limits, header-only

namespace bumprad {

inline std::string describe(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

inline std::string escape_token(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

// Edits (insertions, deletions, substitutions) between two keys, for "did you mean".
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// The candidate a misspelt `key` most likely meant: within two edits (one for short keys).
template <typename Keys>
std::optional<std::string> likely_meant(std::string_view key, const Keys& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = key.size() <= 4 ? 2 : 3;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(key, c);
    if (d > 0 && d < best_distance) best = std::string(c), best_distance = d;
  }
  return best;
}

class Node {
 public:
  using json = nlohmann::json;

  Node(const json& value, std::string pointer) : value_(value), pointer_(std::move(pointer)) {}

  [[noreturn]] void fail(const std::string& reason) const { throw SceneError(pointer_, reason); }
  const std::string& pointer() const { return pointer_; }
  const json& value() const { return value_; }

  Node operator[](std::string_view key) const {
    auto it = object().find(std::string(key));
    if (it == value_.end()) {
      Node missing(value_, pointer_ + "/" + escape_token(key));
      std::vector<std::string> present;
      for (auto k = value_.begin(); k != value_.end(); ++k) present.push_back(k.key());
      std::vector<std::string_view> wanted{key};
      for (const std::string& p : present)
        if (likely_meant(p, wanted))
          missing.fail("is required (the object has \"" + p + "\": a misspelling of \"" +
                       std::string(key) + "\"?)");
      missing.fail("is required");
    }
    return Node(*it, pointer_ + "/" + escape_token(key));
  }
  std::optional<Node> get(std::string_view key) const {
    auto it = object().find(std::string(key));
    if (it == value_.end()) return std::nullopt;
    return Node(*it, pointer_ + "/" + escape_token(key));
  }
  Node operator[](std::size_t i) const {
    return Node(value_[i], pointer_ + "/" + std::to_string(i));
  }

  const json& object() const {
    if (!value_.is_object()) fail("must be an object");
    return value_;
  }
  // Rejects keys not in `keys`; `what` names the kind of object in the message.
  void allow_only(const std::vector<std::string_view>& keys, const std::string& what = "") const {
    for (auto it = object().begin(); it != value_.end(); ++it) {
      if (std::find(keys.begin(), keys.end(), it.key()) != keys.end()) continue;
      std::string list;
      for (auto k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
      const auto meant = likely_meant(it.key(), keys);
      Node(*it, pointer_ + "/" + escape_token(it.key()))
          .fail("unknown key" + (what.empty() ? "" : " for a " + what) + " (" +
                (meant ? "did you mean \"" + *meant + "\"? " : std::string()) +
                "expected one of: " + list + ")");
    }
  }
  std::size_t array(std::size_t min, std::size_t max) const {
    if (!value_.is_array()) fail("must be an array");
    std::size_t n = value_.size();
    if (n < min || n > max) {
      if (min == max)
        fail("must have exactly " + std::to_string(min) + " entries (got " + std::to_string(n) +
             ")");
      fail("must have between " + std::to_string(min) + " and " + std::to_string(max) +
           " entries (got " + std::to_string(n) + ")");
    }
    return n;
  }

  double number() const {
    if (!value_.is_number()) fail("must be a number");
    double x = value_.get<double>();
    if (!std::isfinite(x)) fail("must be a finite number");
    return x;
  }
  double positive() const {
    double x = number();
    if (!(x > 0)) fail("must be greater than 0 (got " + describe(x) + ")");
    return within_limit(x);
  }
  // Coordinates and sizes stay within +-Limits::kMaxMagnitude.
  double within_limit(double x) const {
    if (std::abs(x) > Limits::kMaxMagnitude)
      fail("must be within +-" + describe(Limits::kMaxMagnitude) + " (got " + describe(x) + ")");
    return x;
  }
  double in_range(double lo, double hi, bool hi_open) const {
    double x = number();
    if (x < lo || x > hi || (hi_open && x == hi))
      fail("must be in [" + describe(lo) + ", " + describe(hi) + (hi_open ? ")" : "]") + " (got " +
           describe(x) + ")");
    return x;
  }
  long long integer(long long lo, long long hi) const {
    if (!value_.is_number_integer()) {
      number();
      fail("must be an integer");
    }
    long long x = value_.is_number_unsigned() && value_.get<std::uint64_t>() > std::uint64_t(hi)
                      ? hi + 1
                      : value_.get<long long>();
    if (x < lo || x > hi)
      fail("must be between " + std::to_string(lo) + " and " + std::to_string(hi) + " (got " +
           value_.dump() + ")");
    return x;
  }
  bool boolean() const {
    if (!value_.is_boolean()) fail("must be true or false");
    return value_.get<bool>();
  }
  std::string string() const {
    if (!value_.is_string()) fail("must be a string");
    return value_.get<std::string>();
  }
  // One of a fixed set of names, each standing for a value; `what` names the kind in the
  // message ("unknown texture mode \"x\" (expected none, gather or shoot)").
  template <typename T>
  T one_of(std::initializer_list<std::pair<std::string_view, T>> names, const char* what) const {
    std::string s = string();
    std::string expected;
    std::size_t i = 0;
    for (const auto& [name, value] : names) {
      if (name == s) return value;
      if (i > 0) expected += i + 1 == names.size() ? " or " : ", ";
      expected += name;
      ++i;
    }
    fail("unknown " + std::string(what) + " \"" + s + "\" (expected " + expected + ")");
  }
  Vec3 vec3() const {
    array(3, 3);
    auto at = [&](std::size_t i) { return (*this)[i].within_limit((*this)[i].number()); };
    return {at(0), at(1), at(2)};
  }
  // An RGB triple or one number for all three channels, each in [lo, hi) or [lo, hi].
  Rgb rgb(double lo, double hi, bool hi_open) const {
    if (value_.is_number()) {
      double x = in_range(lo, hi, hi_open);
      return Rgb(x);
    }
    if (!value_.is_array()) fail("must be a number or an array of 3 numbers");
    array(3, 3);
    return {(*this)[0].in_range(lo, hi, hi_open), (*this)[1].in_range(lo, hi, hi_open),
            (*this)[2].in_range(lo, hi, hi_open)};
  }

 private:
  const json& value_;
  std::string pointer_;
};

}  // namespace bumprad
