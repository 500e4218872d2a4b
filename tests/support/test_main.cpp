// main() of every canopy GoogleTest executable. ctest runs each test in its own process and
// two at a time (-j2), so files a test writes under testing::TempDir() must not meet another
// process's: each process gets a private folder (TEST_TMPDIR, which testing::TempDir() reads),
// removed when it ends.

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

int main(int argc, char** argv) {
  const char* parent = std::getenv("TMPDIR");
  std::string pattern = std::string(parent != nullptr && *parent != '\0' ? parent : "/tmp") + "/canopy_test_XXXXXX";
  if (mkdtemp(pattern.data()) == nullptr) {
    std::perror("canopy tests: cannot create a private temporary folder");
    return 2;
  }
  setenv("TEST_TMPDIR", pattern.c_str(), 1);
  testing::InitGoogleTest(&argc, argv);
  const int rc = RUN_ALL_TESTS();
  std::error_code ignored;
  std::filesystem::remove_all(pattern, ignored);
  return rc;
}
