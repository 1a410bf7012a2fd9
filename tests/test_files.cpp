#include "tests/test_files.h"

#include <gtest/gtest.h>

namespace bumprad::test {

std::filesystem::path fresh_temp_dir(const std::string& prefix) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("bumprad-" + prefix + "-" + info->test_suite_name() + "-" + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::remove(dir.string() + ".log");  // a test server's log beside it
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace bumprad::test
