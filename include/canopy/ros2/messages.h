#pragma once
// The ROS 2 messages canopy writes and reads, as plain structs with the fields and names of
// their .msg definitions (ROS 2 Humble; message_schemas.h holds the texts). Each message's
// fields are listed once, in messages.cpp, and serve both encode (CDR out) and decode (CDR in).
//
//   std::string bytes = ros2::serialize(image);                 // CDR, header included
//   auto info = ros2::deserialize<ros2::msg::CameraInfo>(bytes); // InputError when malformed

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "canopy/ros2/cdr.h"

namespace canopy::ros2::msg {

/// builtin_interfaces/msg/Time: seconds and nanoseconds since the epoch of the recording.
struct Time {
  static constexpr const char* kTypeName = "builtin_interfaces/msg/Time";
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  /// From nanoseconds (0 to 2^31 s): the split rosbag2 uses.
  static Time from_ns(std::uint64_t ns);
  /// To nanoseconds; a negative time (before the epoch) gives 0.
  std::uint64_t to_ns() const;
  bool operator==(const Time& o) const { return sec == o.sec && nanosec == o.nanosec; }
};

/// builtin_interfaces/msg/Duration.
struct Duration {
  static constexpr const char* kTypeName = "builtin_interfaces/msg/Duration";
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
};

/// std_msgs/msg/Header: when the data was taken and in which frame.
struct Header {
  static constexpr const char* kTypeName = "std_msgs/msg/Header";
  Time stamp;
  std::string frame_id;
};

/// std_msgs/msg/String.
struct String {
  static constexpr const char* kTypeName = "std_msgs/msg/String";
  std::string data;
};

/// std_msgs/msg/ColorRGBA, each channel in [0, 1].
struct ColorRGBA {
  static constexpr const char* kTypeName = "std_msgs/msg/ColorRGBA";
  float r = 0.0f, g = 0.0f, b = 0.0f, a = 0.0f;
};

/// geometry_msgs/msg/Vector3.
struct Vector3 {
  static constexpr const char* kTypeName = "geometry_msgs/msg/Vector3";
  double x = 0.0, y = 0.0, z = 0.0;
};

/// geometry_msgs/msg/Point.
struct Point {
  static constexpr const char* kTypeName = "geometry_msgs/msg/Point";
  double x = 0.0, y = 0.0, z = 0.0;
};

/// geometry_msgs/msg/Quaternion (identity by default, as its definition's defaults say).
struct Quaternion {
  static constexpr const char* kTypeName = "geometry_msgs/msg/Quaternion";
  double x = 0.0, y = 0.0, z = 0.0, w = 1.0;
};

/// geometry_msgs/msg/Pose.
struct Pose {
  static constexpr const char* kTypeName = "geometry_msgs/msg/Pose";
  Point position;
  Quaternion orientation;
};

/// geometry_msgs/msg/Transform: the child frame's pose in the parent frame.
struct Transform {
  static constexpr const char* kTypeName = "geometry_msgs/msg/Transform";
  Vector3 translation;
  Quaternion rotation;
};

/// geometry_msgs/msg/TransformStamped: header.frame_id is the parent, child_frame_id the child.
struct TransformStamped {
  static constexpr const char* kTypeName = "geometry_msgs/msg/TransformStamped";
  Header header;
  std::string child_frame_id;
  Transform transform;
};

/// tf2_msgs/msg/TFMessage: what /tf and /tf_static carry.
struct TFMessage {
  static constexpr const char* kTypeName = "tf2_msgs/msg/TFMessage";
  std::vector<TransformStamped> transforms;
};

/// sensor_msgs/msg/Image: raw pixels, rows of `step` bytes (encodings: rgb8, mono8, 16UC1 in
/// millimetres, 32FC1 in metres, REP 118).
struct Image {
  static constexpr const char* kTypeName = "sensor_msgs/msg/Image";
  Header header;
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::string encoding;
  std::uint8_t is_bigendian = 0;
  std::uint32_t step = 0;
  std::vector<std::uint8_t> data;
};

/// sensor_msgs/msg/CompressedImage: a PNG or JPEG file's bytes (`format` "png", "jpeg", ...).
struct CompressedImage {
  static constexpr const char* kTypeName = "sensor_msgs/msg/CompressedImage";
  Header header;
  std::string format;
  std::vector<std::uint8_t> data;
};

/// sensor_msgs/msg/RegionOfInterest.
struct RegionOfInterest {
  static constexpr const char* kTypeName = "sensor_msgs/msg/RegionOfInterest";
  std::uint32_t x_offset = 0;
  std::uint32_t y_offset = 0;
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  bool do_rectify = false;
};

/// sensor_msgs/msg/CameraInfo: intrinsics k (row-major 3x3), projection p (3x4), distortion d.
struct CameraInfo {
  static constexpr const char* kTypeName = "sensor_msgs/msg/CameraInfo";
  Header header;
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::string distortion_model;
  std::vector<double> d;
  std::array<double, 9> k{};
  std::array<double, 9> r{};
  std::array<double, 12> p{};
  std::uint32_t binning_x = 0;
  std::uint32_t binning_y = 0;
  RegionOfInterest roi;
};

/// sensor_msgs/msg/PointField: one field of a PointCloud2 point.
struct PointField {
  static constexpr const char* kTypeName = "sensor_msgs/msg/PointField";
  static constexpr std::uint8_t kInt8 = 1, kUint8 = 2, kInt16 = 3, kUint16 = 4, kInt32 = 5, kUint32 = 6,
                                kFloat32 = 7, kFloat64 = 8;
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;
  std::uint32_t count = 0;
};

/// sensor_msgs/msg/PointCloud2: points of `point_step` bytes laid out as `fields` say.
struct PointCloud2 {
  static constexpr const char* kTypeName = "sensor_msgs/msg/PointCloud2";
  Header header;
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::vector<PointField> fields;
  bool is_bigendian = false;
  std::uint32_t point_step = 0;
  std::uint32_t row_step = 0;
  std::vector<std::uint8_t> data;
  bool is_dense = false;
};

/// visualization_msgs/msg/UVCoordinate: a vertex's place in a Marker's texture.
struct UVCoordinate {
  static constexpr const char* kTypeName = "visualization_msgs/msg/UVCoordinate";
  float u = 0.0f, v = 0.0f;
};

/// visualization_msgs/msg/MeshFile: a mesh sent inside a Marker.
struct MeshFile {
  static constexpr const char* kTypeName = "visualization_msgs/msg/MeshFile";
  std::string filename;
  std::vector<std::uint8_t> data;
};

/// visualization_msgs/msg/Marker, the ROS 2 Humble definition (with the texture and mesh_file
/// fields, which Foxy's lacks).
struct Marker {
  static constexpr const char* kTypeName = "visualization_msgs/msg/Marker";
  static constexpr std::int32_t kArrow = 0, kCube = 1, kSphere = 2, kCylinder = 3, kLineStrip = 4, kLineList = 5,
                                kCubeList = 6, kSphereList = 7, kPoints = 8, kTextViewFacing = 9,
                                kMeshResource = 10, kTriangleList = 11;
  static constexpr std::int32_t kAdd = 0, kModify = 0, kDelete = 2, kDeleteAll = 3;
  Header header;
  std::string ns;
  std::int32_t id = 0;
  std::int32_t type = 0;
  std::int32_t action = 0;
  Pose pose;
  Vector3 scale;
  ColorRGBA color;
  Duration lifetime;
  bool frame_locked = false;
  std::vector<Point> points;
  std::vector<ColorRGBA> colors;
  std::string texture_resource;
  CompressedImage texture;
  std::vector<UVCoordinate> uv_coordinates;
  std::string text;
  std::string mesh_resource;
  MeshFile mesh_file;
  bool mesh_use_embedded_materials = false;
};

/// visualization_msgs/msg/MarkerArray.
struct MarkerArray {
  static constexpr const char* kTypeName = "visualization_msgs/msg/MarkerArray";
  std::vector<Marker> markers;
};

// Field lists for CdrWriter / CdrReader (found by argument-dependent lookup).
#define CANOPY_ROS2_MESSAGE(M)         \
  void encode(CdrWriter& cdr, const M& m); \
  void decode(CdrReader& cdr, M& m);
CANOPY_ROS2_MESSAGE(Time)
CANOPY_ROS2_MESSAGE(Duration)
CANOPY_ROS2_MESSAGE(Header)
CANOPY_ROS2_MESSAGE(String)
CANOPY_ROS2_MESSAGE(ColorRGBA)
CANOPY_ROS2_MESSAGE(Vector3)
CANOPY_ROS2_MESSAGE(Point)
CANOPY_ROS2_MESSAGE(Quaternion)
CANOPY_ROS2_MESSAGE(Pose)
CANOPY_ROS2_MESSAGE(Transform)
CANOPY_ROS2_MESSAGE(TransformStamped)
CANOPY_ROS2_MESSAGE(TFMessage)
CANOPY_ROS2_MESSAGE(Image)
CANOPY_ROS2_MESSAGE(CompressedImage)
CANOPY_ROS2_MESSAGE(RegionOfInterest)
CANOPY_ROS2_MESSAGE(CameraInfo)
CANOPY_ROS2_MESSAGE(PointField)
CANOPY_ROS2_MESSAGE(PointCloud2)
CANOPY_ROS2_MESSAGE(UVCoordinate)
CANOPY_ROS2_MESSAGE(MeshFile)
CANOPY_ROS2_MESSAGE(Marker)
CANOPY_ROS2_MESSAGE(MarkerArray)
#undef CANOPY_ROS2_MESSAGE

}  // namespace canopy::ros2::msg

namespace canopy::ros2 {

/// A message's CDR bytes, encapsulation header included: what an MCAP message record holds.
template <class M>
std::string serialize(const M& message) {
  CdrWriter cdr;
  cdr(message);
  return cdr.take();
}

/// The message in CDR `bytes`. Throws InputError (one line naming the type and the offset) when
/// the bytes end early or are not little-endian CDR; trailing padding is allowed.
template <class M>
M deserialize(std::string_view bytes) {
  CdrReader cdr(bytes, M::kTypeName);
  M message;
  cdr(message);
  return message;
}

}  // namespace canopy::ros2
