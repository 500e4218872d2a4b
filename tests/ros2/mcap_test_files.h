#pragma once
// MCAP files for the ros2 tests: a recording with every message type written through
// McapWriter (and what it holds, to compare against), file bytes in and out, and a helper that
// zeroes a file's CRCs so that corruption reaches the reader's own checks.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "canopy/ros2/mcap_writer.h"
#include "sample_messages.h"

namespace canopy::ros2::test {

/// A message as written: its topic, type, times and bytes.
struct Written {
  std::string topic, type;
  std::uint64_t log_time_ns = 0;
  std::string data;
};

inline std::string temp_path(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "ros2";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Writes a recording of `frames` frames: rgb8 and 32FC1 images of `width` x `height`,
/// camera_info, /tf, then /tf_static (stamped at 0, written last: log times go back), a 16UC1
/// depth image, a CompressedImage, a PointCloud2, a MarkerArray and a String once. Returns the
/// messages in the order written.
inline std::vector<Written> write_sample_recording(const std::string& path, const McapWriterOptions& options,
                                                   int frames = 5, std::uint32_t width = 16, std::uint32_t height = 12) {
  McapWriter out(path, options);
  std::vector<Written> written;
  const auto rgb = out.add_channel<msg::Image>("/camera/color/image_raw");
  const auto depth = out.add_channel<msg::Image>("/camera/aligned_depth_to_color/image_raw");
  const auto info = out.add_channel<msg::CameraInfo>("/camera/color/camera_info");
  const auto tf = out.add_channel<msg::TFMessage>("/tf");
  const auto tf_static = out.add_channel<msg::TFMessage>("/tf_static");
  const auto depth16 = out.add_channel<msg::Image>("/camera/depth/image_rect_raw");
  const auto compressed = out.add_channel<msg::CompressedImage>("/camera/color/image_raw/compressed");
  const auto cloud = out.add_channel<msg::PointCloud2>("/canopy/map/cloud");
  const auto markers = out.add_channel<msg::MarkerArray>("/canopy/views");
  const auto text = out.add_channel<msg::String>("/canopy/written_by");
  const auto put = [&](std::uint16_t channel, const std::string& topic, std::uint64_t t, const auto& m) {
    out.write(channel, t, m);
    written.push_back({topic, std::decay_t<decltype(m)>::kTypeName, t, serialize(m)});
  };
  const std::uint64_t t0 = 1700000000000000000ull;
  for (int i = 0; i < frames; ++i) {
    const std::uint64_t t = t0 + std::uint64_t(i) * 100000000ull;
    put(tf, "/tf", t, sample_tf(t, 0.1 * i));
    put(rgb, "/camera/color/image_raw", t + 1000, sample_rgb(width, height, t, i));
    put(depth, "/camera/aligned_depth_to_color/image_raw", t, sample_depth32(width, height, t, i));
    put(info, "/camera/color/camera_info", t + 1000, sample_camera_info(t));
  }
  put(tf_static, "/tf_static", t0, sample_tf_static(t0));
  put(depth16, "/camera/depth/image_rect_raw", t0 + 5, sample_depth16(width, height, t0 + 5));
  put(compressed, "/camera/color/image_raw/compressed", t0 + 6, sample_compressed(t0 + 6));
  put(cloud, "/canopy/map/cloud", t0 + 7, sample_cloud(t0 + 7, 20));
  put(markers, "/canopy/views", t0 + 8, sample_markers(t0 + 8));
  put(text, "/canopy/written_by", t0, msg::String{mcap_library_name()});
  out.close();
  return written;
}

inline std::uint64_t get_u64(const std::string& b, std::size_t at) {
  std::uint64_t v;
  std::memcpy(&v, b.data() + at, 8);
  return v;
}

/// Zeroes the data section CRC, the summary CRC and every chunk's CRC (0: "not available"), so
/// that a corrupted byte reaches the reader's parsing instead of failing a CRC first.
inline std::string without_crcs(std::string b) {
  const std::size_t footer = b.size() - 8 - 29;
  std::memset(b.data() + footer + 25, 0, 4);  // summary_crc
  std::size_t pos = 8;
  while (pos + 9 <= footer) {
    const auto op = static_cast<std::uint8_t>(b[pos]);
    const std::uint64_t len = get_u64(b, pos + 1);
    if (op == 0x06) std::memset(b.data() + pos + 9 + 24, 0, 4);  // chunk uncompressed_crc
    if (op == 0x0F) {
      std::memset(b.data() + pos + 9, 0, 4);  // data_section_crc
      break;
    }
    pos += 9 + len;
  }
  return b;
}

/// The offsets of the records of `op` in the data section.
inline std::vector<std::size_t> data_records(const std::string& b, std::uint8_t op) {
  std::vector<std::size_t> out;
  std::size_t pos = 8;
  while (pos + 9 <= b.size()) {
    const auto o = static_cast<std::uint8_t>(b[pos]);
    if (o == op) out.push_back(pos);
    if (o == 0x0F) break;
    pos += 9 + get_u64(b, pos + 1);
  }
  return out;
}

}  // namespace canopy::ros2::test
