#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/read_file.h"

namespace canopy {
namespace {

TEST(AtomicFile, FailedRenameReportsTheRealError) {
  namespace fs = std::filesystem;
  // Writing a file over a non-empty folder fails in rename(): the message must carry that
  // error, not "Success".
  const std::string target = testing::TempDir() + "/rename_target";
  fs::remove_all(target);
  fs::create_directories(target + "/inside");
  try {
    write_file_atomic(target, "x");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find("Success"), std::string::npos) << msg;
    EXPECT_NE(msg.find(std::error_code(EISDIR, std::generic_category()).message()), std::string::npos) << msg;
  }
  EXPECT_TRUE(fs::is_directory(target + "/inside"));
  // The temporary file was removed.
  for (const auto& e : fs::directory_iterator(testing::TempDir()))
    EXPECT_EQ(e.path().filename().string().find("rename_target.tmp"), std::string::npos) << e.path();
}

// Property: whatever the bytes (empty, binary, NUL, large), what is written is what is read
// back, a second write replaces the first whole, and no temporary file is left beside it.
TEST(AtomicFile, WhatIsWrittenIsReadBackAndNoTemporaryFileStays) {
  namespace fs = std::filesystem;
  const std::string dir = testing::TempDir() + "/atomic_roundtrip";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255);
  const std::string path = dir + "/f.bin";
  for (const std::size_t size : {std::size_t(0), std::size_t(1), std::size_t(4096), std::size_t(100000)}) {
    std::string content(size, '\0');
    for (char& c : content) c = static_cast<char>(byte(rng));
    write_file_atomic(path, content);
    EXPECT_EQ(read_file(path), content) << size;
  }
  write_json_atomic(path, nlohmann::json{{"a", 1}});
  EXPECT_EQ(nlohmann::json::parse(read_file(path)), (nlohmann::json{{"a", 1}}));
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename(), "f.bin");
    ++files;
  }
  EXPECT_EQ(files, 1);
  // Temporary names never repeat, even for the same target.
  EXPECT_NE(unique_temp_path(path), unique_temp_path(path));
}

}  // namespace
}  // namespace canopy
