#pragma once
// Running Foxglove's reference reader and writer (reference/foxglove_reference.mjs, installed
// with its pinned npm packages by the ros2.foxglove_install fixture into the folder
// CANOPY_FOXGLOVE_DIR names) from the ros2 tests, and the small codecs they need to compare.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "canopy/common/process.h"
#include "mcap_test_files.h"

namespace canopy::ros2::test {

/// The folder holding node_modules and the script; "" (and a test failure, never a skip) when
/// the fixture did not install it.
inline std::string foxglove_dir() {
  const char* dir = std::getenv("CANOPY_FOXGLOVE_DIR");
  if (dir == nullptr || !std::filesystem::exists(std::string(dir) + "/node_modules/@mcap/core")) {
    ADD_FAILURE() << "Foxglove's reference libraries are not installed: run the ros2 tests through ctest (the "
                     "ros2.foxglove_install fixture installs them), or set CANOPY_FOXGLOVE_DIR";
    return "";
  }
  return dir;
}

/// Runs the reference script with `args`; false (with its output in the failure) when it fails.
inline bool run_foxglove(const std::vector<std::string>& args) {
  const std::string dir = foxglove_dir();
  if (dir.empty()) return false;
  std::vector<std::string> argv = {"node", dir + "/foxglove_reference.mjs"};
  argv.insert(argv.end(), args.begin(), args.end());
  ProcessOptions options;
  options.output_file = temp_path("node.log");
  options.timeout_s = 300;
  const ProcessStatus status = run_process(argv, options);
  if (!status.ok()) {
    ADD_FAILURE() << "node foxglove_reference.mjs " << args[0] << ": " << status.describe() << "\n"
                  << read_bytes(options.output_file);
    return false;
  }
  return true;
}

inline nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(read_bytes(path)); }

inline std::string base64_decode(const std::string& in) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::string out;
  unsigned buffer = 0;
  int bits = 0;
  for (char c : in) {
    const int v = value(c);
    if (v < 0) continue;  // padding
    buffer = (buffer << 6) | unsigned(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((buffer >> bits) & 0xFF));
    }
  }
  return out;
}

/// A decoded std_msgs/Header (JSON from the reference script) equals `h`.
inline void expect_header(const nlohmann::json& j, const msg::Header& h) {
  EXPECT_EQ(j.at("stamp").at("sec").get<std::int64_t>(), h.stamp.sec);
  EXPECT_EQ(j.at("stamp").at("nanosec").get<std::uint64_t>(), h.stamp.nanosec);
  EXPECT_EQ(j.at("frame_id").get<std::string>(), h.frame_id);
}

/// A JSON array of numbers equals `values` exactly.
template <class Array>
void expect_numbers(const nlohmann::json& j, const Array& values) {
  ASSERT_EQ(j.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(j[i].get<double>(), double(values[i])) << i;
}

/// CRC-32 (ISO-HDLC), as the reference script summarises byte fields.
inline std::uint32_t crc32_of(const std::vector<std::uint8_t>& bytes) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::uint8_t b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
  }
  return c ^ 0xFFFFFFFFu;
}

}  // namespace canopy::ros2::test
