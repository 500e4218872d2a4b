// The test main: each test process gets its own temporary folder (tests/support/test_main.cpp).
#include <gtest/gtest.h>

#include <filesystem>

namespace canopy {
namespace {

TEST(TestSupport, EachTestProcessHasItsOwnTempDir) {
  // ctest -j2 runs two test processes at once; fixed file names under TempDir() must not meet.
  const std::filesystem::path d = testing::TempDir();
  EXPECT_TRUE(std::filesystem::is_directory(d)) << d;
  EXPECT_NE(d.string().find("canopy_test_"), std::string::npos) << d;
  EXPECT_NE(std::filesystem::canonical(d), std::filesystem::canonical(std::filesystem::temp_directory_path()));
}

}  // namespace
}  // namespace canopy
