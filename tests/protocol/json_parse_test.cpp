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

// A missing comma is reported after the value that needs it (an editor shows that line),
// not at the next key where the parser stopped.
TEST(JsonParse, AMissingCommaIsPlacedAfterTheValueBeforeIt) {
  struct Case {
    const char* text;
    std::size_t byte;  // 1-based: the value's last byte
  };
  for (const Case& c :
       {Case{"{\n \"a\": 1\n \"b\": 2\n}", 9}, Case{"{\"a\": [1, 2.5\n 3]}", 13},
        Case{"{\"a\": {\"x\": 1}\n \"b\": 2}", 14}, Case{"{\"a\": \"q\\\"\" \"b\": 1}", 11}}) {
    try {
      parse_json(c.text);
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const MalformedJson& e) {
      EXPECT_NE(e.reason().find("malformed JSON at byte " + std::to_string(c.byte) +
                                ": a comma is missing after this value"),
                std::string::npos)
          << c.text << "\n"
          << e.reason();
    }
  }
  try {  // not a missing comma: said as the parser says it
    parse_json(R"({"a": })");
  } catch (const MalformedJson& e) {
    EXPECT_EQ(e.reason().find("comma"), std::string::npos) << e.reason();
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
