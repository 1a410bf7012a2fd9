// `bumprad serve` and `bumprad worker` refuse what they cannot run before they start: values
// out of range (never clamped), flags of the other command, a worker without a store.
#include <gtest/gtest.h>

#include "tests/test_command.h"

namespace bumprad {
namespace {

test::CommandResult bumprad(const std::string& args) {
  return test::run_command(std::string(BUMPRAD_BIN) + " " + args + " </dev/null");
}

TEST(ServeCli, ValuesOutOfRangeAreRefusedWithTheFlagsName) {
  struct Case {
    const char* args;
    const char* says;
  };
  for (const Case& c : {
           Case{"serve --workers 100",
                "--workers: \"100\" is out of range: give a whole number "
                "from 0 to 64"},
           Case{"serve --port 65536", "--port: \"65536\" is out of range"},
           Case{"serve --keep-steps 0", "--keep-steps: \"0\" is out of range"},
           Case{"serve --max-attempts 101", "--max-attempts: \"101\" is out of range"},
           Case{"serve --body-limit 1X", "--body-limit: \"1X\" is not a whole number"},
           Case{"serve --workers 0", "--workers: at least 1 without --store"},
           Case{"serve --max-queue", "--max-queue needs a value"},
           Case{"serve --colour blue", "unknown option --colour"},
           Case{"serve --store ''", "--store: empty; name a database"},
           Case{"serve --max-image-memory 1K", "--max-image-memory: \"1K\" is out of range"},
           Case{"worker --workers 2", "--store postgresql://... is required"},
           Case{"worker --store postgresql://db/x --port 80", "--port is for bumprad serve"},
           Case{"worker --store postgresql://db/x --workers 0", "--workers: at least 1"},
       }) {
    const test::CommandResult r = bumprad(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find("usage: bumprad"), std::string::npos) << c.args;
  }
}

// A refused store URL is named without its password.
TEST(ServeCli, AStoreUrlIsNeverEchoedWithItsPassword) {
  const test::CommandResult r = bumprad("serve --store mysql://reader:s3cret@db.example/jobs");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("\"mysql://reader:***@db.example/jobs\" is not a postgresql:// URL"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("s3cret"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace bumprad
