#include "canopy/ros2/message_schemas.h"

#include <algorithm>
#include <set>

#include "canopy/common/error.h"

namespace canopy::ros2 {

namespace {

// One type: its name, its .msg text (ROS 2 Humble, comments left out; same-package types
// unqualified as in the .msg files) and the types its fields use.
struct Definition {
  const char* name;
  const char* text;
  std::vector<const char*> uses;
};

const std::vector<Definition>& definitions() {
  static const std::vector<Definition> table = {
      {"builtin_interfaces/msg/Time", "int32 sec\nuint32 nanosec\n", {}},
      {"builtin_interfaces/msg/Duration", "int32 sec\nuint32 nanosec\n", {}},
      {"std_msgs/msg/Header", "builtin_interfaces/Time stamp\nstring frame_id\n", {"builtin_interfaces/msg/Time"}},
      {"std_msgs/msg/String", "string data\n", {}},
      {"std_msgs/msg/ColorRGBA", "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n", {}},
      {"geometry_msgs/msg/Vector3", "float64 x\nfloat64 y\nfloat64 z\n", {}},
      {"geometry_msgs/msg/Point", "float64 x\nfloat64 y\nfloat64 z\n", {}},
      {"geometry_msgs/msg/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n", {}},
      {"geometry_msgs/msg/Pose",
       "Point position\nQuaternion orientation\n",
       {"geometry_msgs/msg/Point", "geometry_msgs/msg/Quaternion"}},
      {"geometry_msgs/msg/Transform",
       "Vector3 translation\nQuaternion rotation\n",
       {"geometry_msgs/msg/Vector3", "geometry_msgs/msg/Quaternion"}},
      {"geometry_msgs/msg/TransformStamped",
       "std_msgs/Header header\nstring child_frame_id\nTransform transform\n",
       {"std_msgs/msg/Header", "geometry_msgs/msg/Transform"}},
      {"tf2_msgs/msg/TFMessage",
       "geometry_msgs/TransformStamped[] transforms\n",
       {"geometry_msgs/msg/TransformStamped"}},
      {"sensor_msgs/msg/Image",
       "std_msgs/Header header\n"
       "uint32 height\n"
       "uint32 width\n"
       "string encoding\n"
       "uint8 is_bigendian\n"
       "uint32 step\n"
       "uint8[] data\n",
       {"std_msgs/msg/Header"}},
      {"sensor_msgs/msg/CompressedImage",
       "std_msgs/Header header\nstring format\nuint8[] data\n",
       {"std_msgs/msg/Header"}},
      {"sensor_msgs/msg/RegionOfInterest",
       "uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n",
       {}},
      {"sensor_msgs/msg/CameraInfo",
       "std_msgs/Header header\n"
       "uint32 height\n"
       "uint32 width\n"
       "string distortion_model\n"
       "float64[] d\n"
       "float64[9] k\n"
       "float64[9] r\n"
       "float64[12] p\n"
       "uint32 binning_x\n"
       "uint32 binning_y\n"
       "RegionOfInterest roi\n",
       {"std_msgs/msg/Header", "sensor_msgs/msg/RegionOfInterest"}},
      {"sensor_msgs/msg/PointField",
       "uint8 INT8    = 1\n"
       "uint8 UINT8   = 2\n"
       "uint8 INT16   = 3\n"
       "uint8 UINT16  = 4\n"
       "uint8 INT32   = 5\n"
       "uint8 UINT32  = 6\n"
       "uint8 FLOAT32 = 7\n"
       "uint8 FLOAT64 = 8\n"
       "string name\n"
       "uint32 offset\n"
       "uint8 datatype\n"
       "uint32 count\n",
       {}},
      {"sensor_msgs/msg/PointCloud2",
       "std_msgs/Header header\n"
       "uint32 height\n"
       "uint32 width\n"
       "PointField[] fields\n"
       "bool is_bigendian\n"
       "uint32 point_step\n"
       "uint32 row_step\n"
       "uint8[] data\n"
       "bool is_dense\n",
       {"std_msgs/msg/Header", "sensor_msgs/msg/PointField"}},
      {"visualization_msgs/msg/UVCoordinate", "float32 u\nfloat32 v\n", {}},
      {"visualization_msgs/msg/MeshFile", "string filename\nuint8[] data\n", {}},
      {"visualization_msgs/msg/Marker",
       "int32 ARROW=0\n"
       "int32 CUBE=1\n"
       "int32 SPHERE=2\n"
       "int32 CYLINDER=3\n"
       "int32 LINE_STRIP=4\n"
       "int32 LINE_LIST=5\n"
       "int32 CUBE_LIST=6\n"
       "int32 SPHERE_LIST=7\n"
       "int32 POINTS=8\n"
       "int32 TEXT_VIEW_FACING=9\n"
       "int32 MESH_RESOURCE=10\n"
       "int32 TRIANGLE_LIST=11\n"
       "\n"
       "int32 ADD=0\n"
       "int32 MODIFY=0\n"
       "int32 DELETE=2\n"
       "int32 DELETEALL=3\n"
       "\n"
       "std_msgs/Header header\n"
       "string ns\n"
       "int32 id\n"
       "int32 type\n"
       "int32 action\n"
       "geometry_msgs/Pose pose\n"
       "geometry_msgs/Vector3 scale\n"
       "std_msgs/ColorRGBA color\n"
       "builtin_interfaces/Duration lifetime\n"
       "bool frame_locked\n"
       "geometry_msgs/Point[] points\n"
       "std_msgs/ColorRGBA[] colors\n"
       "string texture_resource\n"
       "sensor_msgs/CompressedImage texture\n"
       "UVCoordinate[] uv_coordinates\n"
       "string text\n"
       "string mesh_resource\n"
       "MeshFile mesh_file\n"
       "bool mesh_use_embedded_materials\n",
       {"std_msgs/msg/Header", "geometry_msgs/msg/Pose", "geometry_msgs/msg/Vector3", "std_msgs/msg/ColorRGBA",
        "builtin_interfaces/msg/Duration", "geometry_msgs/msg/Point", "sensor_msgs/msg/CompressedImage",
        "visualization_msgs/msg/UVCoordinate", "visualization_msgs/msg/MeshFile"}},
      {"visualization_msgs/msg/MarkerArray", "Marker[] markers\n", {"visualization_msgs/msg/Marker"}},
  };
  return table;
}

const Definition* find(std::string_view name) {
  for (const Definition& d : definitions())
    if (name == d.name) return &d;
  return nullptr;
}

// "sensor_msgs/msg/Image" -> "sensor_msgs/Image", the name a MSG: line gives.
std::string short_name(std::string_view full) {
  std::string s(full);
  const auto at = s.find("/msg/");
  if (at != std::string::npos) s.erase(at, 4);
  return s;
}

// The types `d` uses, directly or not, each once, in the order they are first met.
void collect_uses(const Definition& d, std::vector<const Definition*>& out, std::set<std::string>& seen) {
  for (const char* use : d.uses) {
    if (!seen.insert(use).second) continue;
    const Definition* u = find(use);
    CANOPY_CHECK(u != nullptr, "ros2 schema table: " << d.name << " uses unknown " << use);
    out.push_back(u);
    collect_uses(*u, out, seen);
  }
}

}  // namespace

std::string ros2msg_schema(std::string_view type_name) {
  const Definition* d = find(type_name);
  if (d == nullptr) {
    std::string known;
    for (const std::string& t : known_message_types()) known += (known.empty() ? "" : ", ") + t;
    throw InputError("no ros2msg schema for message type '" + std::string(type_name) + "' (canopy knows " + known +
                     ")");
  }
  std::vector<const Definition*> uses;
  std::set<std::string> seen{d->name};
  collect_uses(*d, uses, seen);
  std::string text = d->text;
  for (const Definition* u : uses) {
    text += std::string(80, '=') + "\n";
    text += "MSG: " + short_name(u->name) + "\n";
    text += u->text;
  }
  return text;
}

std::string_view ros2msg_definition(std::string_view type_name) {
  const Definition* d = find(type_name);
  return d == nullptr ? std::string_view() : std::string_view(d->text);
}

std::vector<std::string> known_message_types() {
  std::vector<std::string> out;
  for (const Definition& d : definitions()) out.emplace_back(d.name);
  return out;
}

}  // namespace canopy::ros2
