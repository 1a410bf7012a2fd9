// JSON from outside: parsed when well-formed, refused with where and why when not, and
// refused past kMaxJsonDepth before anything recurses over it.
#include "protocol/json_parse.h"

#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace bumprad {
namespace {

std::string nested(int depth) {
  return std::string(std::size_t(depth), '[') + std::string(std::size_t(depth), ']');
}

TEST(JsonParse, WellFormedTextParses) {
  const auto j = parse_json(R"({"a": [1, 2, {"b": "c"}], "d": null})");
  EXPECT_EQ(j["a"][2]["b"], "c");
  EXPECT_NO_THROW(parse_json(nested(kMaxJsonDepth)));
}

TEST(JsonParse, MalformedTextSaysWhereAndWhy) {
  for (const char* bad : {"", "{", R"({"a": })", "[1, 2,]", "nul", R"({"a" 1})"}) {
    try {
      parse_json(bad);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const MalformedJson& e) {
      EXPECT_TRUE(e.pointer().empty());
      EXPECT_FALSE(e.reason().empty()) << bad;
    }
  }
}

TEST(JsonParse, NestingPastTheLimitIsRefused) {
  for (int depth : {kMaxJsonDepth + 1, 100000}) {
    try {
      parse_json(nested(depth));
      ADD_FAILURE() << depth;
    } catch (const MalformedJson& e) {
      EXPECT_NE(std::string(e.what()).find(std::to_string(kMaxJsonDepth)), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace bumprad
