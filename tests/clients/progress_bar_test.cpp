// The terminal progress line of `bumprad-client submit --watch`.
#include "clients/progress_bar.h"

#include <gtest/gtest.h>

namespace bumprad {
namespace {

TEST(ProgressBar, FillsInProportionToTheShots) {
  EXPECT_EQ(progress_line(300, 600, 0.1234, 5, 3.21, 10),
            "[#####-----]  50%  300/600 shots  unshot 12.34%  step 5  3.2 s");
  EXPECT_EQ(progress_line(0, 600, 1, 0, 0, 4),
            "[----]   0%  0/600 shots  unshot 100.00%  step 0  0.0 s");
  EXPECT_EQ(progress_line(600, 600, 0.01, 20, 9, 4).substr(0, 11), "[####] 100%");
  EXPECT_EQ(progress_line(900, 600, 0.01, 20, 9, 4).substr(0, 11), "[####] 100%");
  EXPECT_EQ(progress_line(5, 0, 0.5, 1, 1, 4).substr(0, 11), "[----]   0%");
}

}  // namespace
}  // namespace bumprad
