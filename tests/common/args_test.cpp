// The one argument parser: values read whole and range-checked, errors that name the flag,
// nothing clamped.
#include "common/args.h"

#include <gtest/gtest.h>

namespace bumprad {
namespace {

std::string error_of(ArgParser& p, std::vector<std::string_view> args) {
  try {
    p.parse(args);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

TEST(Args, ValuesGoWhereTheyAreDeclared) {
  std::string out;
  int shots = 0;
  double tolerance = 0;
  bool watch = false;
  std::vector<std::string> positional;
  ArgParser p;
  p.text({"-o", "--output"}, out)
      .integer({"--shots"}, shots, 1, 100)
      .number({"--tolerance"}, tolerance, 0, 1)
      .toggle({"--watch"}, watch)
      .positional(positional, 1);
  p.parse(std::vector<std::string_view>{"scene.json", "--output", "a.png", "--shots=42",
                                        "--tolerance", "2e-2", "--watch"});
  EXPECT_EQ(out, "a.png");
  EXPECT_EQ(shots, 42);
  EXPECT_EQ(tolerance, 0.02);
  EXPECT_TRUE(watch);
  EXPECT_EQ(positional, std::vector<std::string>{"scene.json"});
  EXPECT_TRUE(p.given("-o"));
  EXPECT_TRUE(p.given("--output"));
  EXPECT_FALSE(ArgParser(p).given("--nothing"));
}

TEST(Args, OutOfRangeIsRefusedWithTheFlagsNameNotClamped) {
  int workers = 1;
  ArgParser p;
  p.integer({"--workers"}, workers, 0, 64);
  EXPECT_EQ(error_of(p, {"--workers", "100"}),
            "--workers: \"100\" is out of range: give a whole number from 0 to 64");
  EXPECT_EQ(workers, 1);
  EXPECT_EQ(error_of(p, {"--workers", "99999999999999999999"}),
            "--workers: \"99999999999999999999\" is out of range: give a whole number from 0 to "
            "64");
  double t = 0;
  ArgParser q;
  q.number({"--tolerance"}, t, 0, 1);
  EXPECT_EQ(error_of(q, {"--tolerance", "1.5"}),
            "--tolerance: \"1.5\" is out of range: give a number from 0 to 1");
}

TEST(Args, TheWholeValueIsRead) {
  int n = 0;
  double x = 0;
  ArgParser p;
  p.integer({"-n"}, n, 0, 1000).number({"-x"}, x, -10, 10);
  for (const char* bad : {"12abc", "", " 12", "1.5", "0x10", "+-1"})
    EXPECT_EQ(error_of(p, {"-n", bad}), std::string("-n: \"") + bad + "\" is not a whole number")
        << bad;
  for (const char* bad : {"1.5.2", "nan", "inf", "1e400", "", "two"})
    EXPECT_EQ(error_of(p, {"-x", bad}), std::string("-x: \"") + bad + "\" is not a number") << bad;
  EXPECT_EQ(n, 0);
}

TEST(Args, SizesTakeSuffixes) {
  std::uint64_t bytes = 0;
  ArgParser p;
  p.integer({"--max-bytes"}, bytes, 1, INT64_MAX, true);
  p.parse(std::vector<std::string_view>{"--max-bytes", "4G"});
  EXPECT_EQ(bytes, std::uint64_t(4) << 30);
  p.parse(std::vector<std::string_view>{"--max-bytes=512K"});
  EXPECT_EQ(bytes, 512u << 10);
  EXPECT_EQ(error_of(p, {"--max-bytes", "4T"}),
            "--max-bytes: \"4T\" is not a whole number (with an optional K, M or G)");
  EXPECT_EQ(error_of(p, {"--max-bytes", "0K"}),
            "--max-bytes: \"0K\" is out of range: give a whole number from 1 to "
            "9223372036854775807");
  EXPECT_NE(error_of(p, {"--max-bytes", "9999999999999G"}).find("out of range"), std::string::npos);
}

TEST(Args, UnknownFlagsMissingValuesAndExtraArgumentsAreErrors) {
  std::string out;
  bool watch = false;
  std::vector<std::string> positional;
  ArgParser p;
  p.text({"-o"}, out).toggle({"--watch"}, watch).positional(positional, 1);
  EXPECT_EQ(error_of(p, {"--shots", "3"}), "unknown option --shots");
  EXPECT_EQ(error_of(p, {"-o"}), "-o needs a value");
  EXPECT_EQ(error_of(p, {"--watch=yes"}), "--watch takes no value");
  positional.clear();
  EXPECT_EQ(error_of(p, {"a.json", "b.json"}), "unexpected argument \"b.json\"");
  ArgParser none;
  EXPECT_EQ(error_of(none, {"a.json"}), "unexpected argument \"a.json\"");
}

}  // namespace
}  // namespace bumprad
