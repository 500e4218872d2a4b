#pragma once
// Deterministic ROS 2 messages of every type messages.h has, for the ros2 tests: each field
// set to a value of its own, so a field lost, swapped or misaligned changes the bytes.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "canopy/ros2/messages.h"

namespace canopy::ros2::test {

inline msg::Header sample_header(std::uint64_t stamp_ns, const std::string& frame) {
  msg::Header h;
  h.stamp = msg::Time::from_ns(stamp_ns);
  h.frame_id = frame;
  return h;
}

/// An image of `width` x `height` pixels of `bytes_per_pixel` bytes, all zero.
inline msg::Image blank_image(std::uint32_t width, std::uint32_t height, const char* encoding,
                              std::uint32_t bytes_per_pixel, std::uint64_t stamp_ns, const std::string& frame) {
  msg::Image m;
  m.header = sample_header(stamp_ns, frame);
  m.width = width;
  m.height = height;
  m.encoding = encoding;
  m.step = width * bytes_per_pixel;
  m.data.resize(std::size_t(m.step) * height);
  return m;
}

/// An rgb8 image whose pixels depend on `seed`.
inline msg::Image sample_rgb(std::uint32_t width, std::uint32_t height, std::uint64_t stamp_ns, int seed) {
  msg::Image m = blank_image(width, height, "rgb8", 3, stamp_ns, "camera_color_optical_frame");
  for (std::size_t i = 0; i < m.data.size(); ++i) m.data[i] = static_cast<std::uint8_t>((i * 7 + seed * 13 + i / 640) & 0xFF);
  return m;
}

/// A 32FC1 depth image in metres with NaN where there is no return (REP 118).
inline msg::Image sample_depth32(std::uint32_t width, std::uint32_t height, std::uint64_t stamp_ns, int seed) {
  msg::Image m = blank_image(width, height, "32FC1", 4, stamp_ns, "camera_color_optical_frame");
  for (std::size_t i = 0; i < m.data.size() / 4; ++i) {
    const float metres = (i % 97 == 0) ? std::numeric_limits<float>::quiet_NaN() : 0.3f + 0.001f * float((i + seed) % 500);
    std::memcpy(m.data.data() + 4 * i, &metres, 4);
  }
  return m;
}

/// A 16UC1 depth image in millimetres, 0 for no return.
inline msg::Image sample_depth16(std::uint32_t width, std::uint32_t height, std::uint64_t stamp_ns) {
  msg::Image m = blank_image(width, height, "16UC1", 2, stamp_ns, "camera_depth_optical_frame");
  for (std::size_t i = 0; i < m.data.size() / 2; ++i) {
    const std::uint16_t mm = (i % 11 == 0) ? 0 : static_cast<std::uint16_t>(300 + i % 900);
    std::memcpy(m.data.data() + 2 * i, &mm, 2);
  }
  return m;
}

inline msg::CompressedImage sample_compressed(std::uint64_t stamp_ns) {
  msg::CompressedImage m;
  m.header = sample_header(stamp_ns, "camera_color_optical_frame");
  m.format = "png";
  // Any bytes: a reader passes them on untouched.
  m.data = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R', 1, 2, 3};
  return m;
}

inline msg::CameraInfo sample_camera_info(std::uint64_t stamp_ns) {
  msg::CameraInfo m;
  m.header = sample_header(stamp_ns, "camera_color_optical_frame");
  m.width = 640;
  m.height = 480;
  m.distortion_model = "plumb_bob";
  m.d = {0.01, -0.02, 0.001, 0.0005, 0.0};
  m.k = {615.5, 0, 320.25, 0, 615.75, 240.5, 0, 0, 1};
  m.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.p = {615.5, 0, 320.25, 0, 0, 615.75, 240.5, 0, 0, 0, 1, 0};
  m.binning_x = 1;
  m.binning_y = 2;
  m.roi.x_offset = 3;
  m.roi.y_offset = 4;
  m.roi.width = 600;
  m.roi.height = 400;
  m.roi.do_rectify = true;
  return m;
}

inline msg::TransformStamped sample_transform(std::uint64_t stamp_ns, const std::string& parent,
                                              const std::string& child, double x) {
  msg::TransformStamped t;
  t.header = sample_header(stamp_ns, parent);
  t.child_frame_id = child;
  t.transform.translation.x = x;
  t.transform.translation.y = -0.25;
  t.transform.translation.z = 1.125;
  const double half = 0.5 * (0.1 + x);
  t.transform.rotation.z = std::sin(half);
  t.transform.rotation.w = std::cos(half);
  return t;
}

/// /tf: the arm's chain at one stamp.
inline msg::TFMessage sample_tf(std::uint64_t stamp_ns, double x) {
  msg::TFMessage m;
  m.transforms.push_back(sample_transform(stamp_ns, "world", "base_link", x));
  m.transforms.push_back(sample_transform(stamp_ns, "base_link", "tool0", 0.5 * x));
  return m;
}

/// /tf_static: the camera's fixed links.
inline msg::TFMessage sample_tf_static(std::uint64_t stamp_ns) {
  msg::TFMessage m;
  m.transforms.push_back(sample_transform(stamp_ns, "tool0", "camera_link", 0.05));
  m.transforms.push_back(sample_transform(stamp_ns, "camera_link", "camera_color_optical_frame", 0.0));
  return m;
}

inline msg::PointCloud2 sample_cloud(std::uint64_t stamp_ns, std::uint32_t points) {
  msg::PointCloud2 m;
  m.header = sample_header(stamp_ns, "world");
  m.height = 1;
  m.width = points;
  const char* names[] = {"x", "y", "z"};
  for (std::uint32_t i = 0; i < 3; ++i) {
    msg::PointField f;
    f.name = names[i];
    f.offset = 4 * i;
    f.datatype = msg::PointField::kFloat32;
    f.count = 1;
    m.fields.push_back(f);
  }
  msg::PointField label;
  label.name = "label";
  label.offset = 12;
  label.datatype = msg::PointField::kUint8;
  label.count = 1;
  m.fields.push_back(label);
  m.point_step = 16;
  m.row_step = 16 * points;
  m.data.resize(m.row_step);
  for (std::uint32_t i = 0; i < points; ++i) {
    const float xyz[3] = {0.01f * float(i), -0.02f * float(i), 1.0f};
    std::memcpy(m.data.data() + 16 * i, xyz, 12);
    m.data[16 * i + 12] = static_cast<std::uint8_t>(i % 3);
  }
  m.is_dense = true;
  return m;
}

inline msg::MarkerArray sample_markers(std::uint64_t stamp_ns) {
  msg::MarkerArray a;
  msg::Marker m;
  m.header = sample_header(stamp_ns, "world");
  m.ns = "views";
  m.id = 7;
  m.type = msg::Marker::kLineList;
  m.action = msg::Marker::kAdd;
  m.pose.position.x = 0.5;
  m.pose.orientation.w = 1.0;
  m.scale.x = 0.005;
  m.color = {0.1f, 0.8f, 0.2f, 1.0f};
  m.lifetime.sec = 2;
  m.lifetime.nanosec = 500;
  m.frame_locked = true;
  for (int i = 0; i < 4; ++i) {
    msg::Point p;
    p.x = i;
    p.y = -i;
    p.z = 0.5 * i;
    m.points.push_back(p);
    m.colors.push_back({0.25f * float(i), 0.0f, 1.0f, 0.5f});
  }
  m.texture_resource = "embedded://leaf";
  m.texture = sample_compressed(stamp_ns);
  m.uv_coordinates = {{0.0f, 1.0f}, {0.5f, 0.25f}};
  m.text = "view 7";
  m.mesh_resource = "embedded://pepper";
  m.mesh_file.filename = "pepper.stl";
  m.mesh_file.data = {1, 2, 3, 4, 5};
  m.mesh_use_embedded_materials = true;
  a.markers.push_back(m);
  msg::Marker text;
  text.header = m.header;
  text.ns = "labels";
  text.id = 8;
  text.type = msg::Marker::kTextViewFacing;
  text.text = "fruit 3";
  a.markers.push_back(text);
  return a;
}

}  // namespace canopy::ros2::test
