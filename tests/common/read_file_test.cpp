#include <gtest/gtest.h>

#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/read_file.h"

namespace canopy {
namespace {

// Inputs that never end or are larger than the limit are refused before anything is allocated.
TEST(ReadFile, RefusesDevicesAndFilesOverTheLimit) {
  EXPECT_THROW(read_file("/dev/zero"), InputError);
  const std::string big = testing::TempDir() + "/big.txt";
  write_file_atomic(big, std::string(2000, 'x'));
  EXPECT_THROW(read_file(big, 1000), InputError);
  EXPECT_EQ(read_file(big).size(), 2000u);
}

TEST(ReadFile, AFolderOrAMissingFileIsAnInputError) {
  EXPECT_THROW(read_file(testing::TempDir()), InputError);
  EXPECT_THROW(read_file(testing::TempDir() + "/no_such_file.txt"), InputError);
  // A file exactly at the limit is read whole.
  const std::string edge = testing::TempDir() + "/edge.txt";
  write_file_atomic(edge, std::string(1000, 'y'));
  EXPECT_EQ(read_file(edge, 1000), std::string(1000, 'y'));
}

}  // namespace
}  // namespace canopy
