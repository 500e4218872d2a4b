// Warnings go to the handler a front end set, else to stderr; setting one returns the previous.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "canopy/common/warning.h"

using namespace canopy;

TEST(Warning, GoesToTheHandlerSetAndBackToStderr) {
  std::vector<std::string> seen;
  const auto before = set_warning_handler([&](const std::string& line) { seen.push_back(line); });
  warn("first");
  warn("second");
  EXPECT_EQ(seen, (std::vector<std::string>{"first", "second"}));
  // Setting another hands back ours; null goes back to stderr.
  const auto ours = set_warning_handler(nullptr);
  ASSERT_TRUE(ours);
  ours("third");
  EXPECT_EQ(seen.size(), 3u);
  ::testing::internal::CaptureStderr();
  warn("to stderr");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "canopy: warning: to stderr\n");
  EXPECT_EQ(seen.size(), 3u);
  set_warning_handler(before);
}
