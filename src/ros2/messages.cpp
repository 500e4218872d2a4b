#include "canopy/ros2/messages.h"

namespace canopy::ros2::msg {

namespace {
constexpr std::uint64_t kNsPerS = 1000000000ull;

// Each message's fields, in the order of its .msg definition: the one list both directions use.
// `M` is the message, const for encoding.
template <class C, class M> void fields_time(C& c, M& m) { c(m.sec); c(m.nanosec); }
template <class C, class M> void fields_header(C& c, M& m) { c(m.stamp); c(m.frame_id); }
template <class C, class M> void fields_string(C& c, M& m) { c(m.data); }
template <class C, class M> void fields_color(C& c, M& m) { c(m.r); c(m.g); c(m.b); c(m.a); }
template <class C, class M> void fields_xyz(C& c, M& m) { c(m.x); c(m.y); c(m.z); }
template <class C, class M> void fields_quaternion(C& c, M& m) { c(m.x); c(m.y); c(m.z); c(m.w); }
template <class C, class M> void fields_pose(C& c, M& m) { c(m.position); c(m.orientation); }
template <class C, class M> void fields_transform(C& c, M& m) { c(m.translation); c(m.rotation); }
template <class C, class M> void fields_transform_stamped(C& c, M& m) {
  c(m.header);
  c(m.child_frame_id);
  c(m.transform);
}
template <class C, class M> void fields_tf(C& c, M& m) { c(m.transforms); }
template <class C, class M> void fields_image(C& c, M& m) {
  c(m.header);
  c(m.height);
  c(m.width);
  c(m.encoding);
  c(m.is_bigendian);
  c(m.step);
  c(m.data);
}
template <class C, class M> void fields_compressed_image(C& c, M& m) {
  c(m.header);
  c(m.format);
  c(m.data);
}
template <class C, class M> void fields_roi(C& c, M& m) {
  c(m.x_offset);
  c(m.y_offset);
  c(m.height);
  c(m.width);
  c(m.do_rectify);
}
template <class C, class M> void fields_camera_info(C& c, M& m) {
  c(m.header);
  c(m.height);
  c(m.width);
  c(m.distortion_model);
  c(m.d);
  c(m.k);
  c(m.r);
  c(m.p);
  c(m.binning_x);
  c(m.binning_y);
  c(m.roi);
}
template <class C, class M> void fields_point_field(C& c, M& m) {
  c(m.name);
  c(m.offset);
  c(m.datatype);
  c(m.count);
}
template <class C, class M> void fields_point_cloud(C& c, M& m) {
  c(m.header);
  c(m.height);
  c(m.width);
  c(m.fields);
  c(m.is_bigendian);
  c(m.point_step);
  c(m.row_step);
  c(m.data);
  c(m.is_dense);
}
template <class C, class M> void fields_uv(C& c, M& m) { c(m.u); c(m.v); }
template <class C, class M> void fields_mesh_file(C& c, M& m) { c(m.filename); c(m.data); }
template <class C, class M> void fields_marker(C& c, M& m) {
  c(m.header);
  c(m.ns);
  c(m.id);
  c(m.type);
  c(m.action);
  c(m.pose);
  c(m.scale);
  c(m.color);
  c(m.lifetime);
  c(m.frame_locked);
  c(m.points);
  c(m.colors);
  c(m.texture_resource);
  c(m.texture);
  c(m.uv_coordinates);
  c(m.text);
  c(m.mesh_resource);
  c(m.mesh_file);
  c(m.mesh_use_embedded_materials);
}
template <class C, class M> void fields_marker_array(C& c, M& m) { c(m.markers); }
}  // namespace

Time Time::from_ns(std::uint64_t ns) {
  Time t;
  t.sec = static_cast<std::int32_t>(ns / kNsPerS);
  t.nanosec = static_cast<std::uint32_t>(ns % kNsPerS);
  return t;
}

std::uint64_t Time::to_ns() const {
  if (sec < 0) return 0;
  return static_cast<std::uint64_t>(sec) * kNsPerS + nanosec;
}

#define CANOPY_ROS2_FIELDS(M, fields)                       \
  void encode(CdrWriter& cdr, const M& m) { fields(cdr, m); } \
  void decode(CdrReader& cdr, M& m) { fields(cdr, m); }
CANOPY_ROS2_FIELDS(Time, fields_time)
CANOPY_ROS2_FIELDS(Duration, fields_time)
CANOPY_ROS2_FIELDS(Header, fields_header)
CANOPY_ROS2_FIELDS(String, fields_string)
CANOPY_ROS2_FIELDS(ColorRGBA, fields_color)
CANOPY_ROS2_FIELDS(Vector3, fields_xyz)
CANOPY_ROS2_FIELDS(Point, fields_xyz)
CANOPY_ROS2_FIELDS(Quaternion, fields_quaternion)
CANOPY_ROS2_FIELDS(Pose, fields_pose)
CANOPY_ROS2_FIELDS(Transform, fields_transform)
CANOPY_ROS2_FIELDS(TransformStamped, fields_transform_stamped)
CANOPY_ROS2_FIELDS(TFMessage, fields_tf)
CANOPY_ROS2_FIELDS(Image, fields_image)
CANOPY_ROS2_FIELDS(CompressedImage, fields_compressed_image)
CANOPY_ROS2_FIELDS(RegionOfInterest, fields_roi)
CANOPY_ROS2_FIELDS(CameraInfo, fields_camera_info)
CANOPY_ROS2_FIELDS(PointField, fields_point_field)
CANOPY_ROS2_FIELDS(PointCloud2, fields_point_cloud)
CANOPY_ROS2_FIELDS(UVCoordinate, fields_uv)
CANOPY_ROS2_FIELDS(MeshFile, fields_mesh_file)
CANOPY_ROS2_FIELDS(Marker, fields_marker)
CANOPY_ROS2_FIELDS(MarkerArray, fields_marker_array)
#undef CANOPY_ROS2_FIELDS

}  // namespace canopy::ros2::msg
