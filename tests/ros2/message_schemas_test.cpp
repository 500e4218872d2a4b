// The ros2msg schema texts: the definition, then each type used after a line of 80 '=' and
// `MSG: pkg/Type`; every complex field type of every section has its own section.
#include "canopy/ros2/message_schemas.h"

#include <gtest/gtest.h>

#include <set>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/ros2/messages.h"
#include "expect_input_error.h"

namespace canopy::ros2 {
namespace {

const std::string kSeparator(80, '=');

TEST(MessageSchemas, ImageIsItsDefinitionThenHeaderThenTime) {
  const std::string expected = "std_msgs/Header header\n"
                               "uint32 height\n"
                               "uint32 width\n"
                               "string encoding\n"
                               "uint8 is_bigendian\n"
                               "uint32 step\n"
                               "uint8[] data\n" +
                               kSeparator + "\nMSG: std_msgs/Header\n" +
                               "builtin_interfaces/Time stamp\nstring frame_id\n" + kSeparator +
                               "\nMSG: builtin_interfaces/Time\n" + "int32 sec\nuint32 nanosec\n";
  EXPECT_EQ(ros2msg_schema(msg::Image::kTypeName), expected);
}

// The sections of a schema text: (name, lines); the first has the name "".
std::vector<std::pair<std::string, std::vector<std::string>>> sections(const std::string& text) {
  std::vector<std::pair<std::string, std::vector<std::string>>> out(1);
  std::istringstream in(text);
  std::string line;
  bool expect_msg = false;
  while (std::getline(in, line)) {
    if (line == kSeparator) {
      expect_msg = true;
      continue;
    }
    if (expect_msg) {
      EXPECT_EQ(line.rfind("MSG: ", 0), 0u) << "after a separator: " << line;
      out.emplace_back(line.substr(5), std::vector<std::string>{});
      expect_msg = false;
      continue;
    }
    if (!line.empty()) out.back().second.push_back(line);
  }
  return out;
}

TEST(MessageSchemas, EveryUsedTypeHasItsSectionOnce) {
  const std::set<std::string> builtin = {"bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32",
                                         "uint32", "int64", "uint64", "float32", "float64", "string"};
  for (const std::string& type : known_message_types()) {
    const auto parts = sections(ros2msg_schema(type));
    std::set<std::string> names;
    for (std::size_t i = 1; i < parts.size(); ++i) {
      EXPECT_TRUE(names.insert(parts[i].first).second) << type << ": " << parts[i].first << " twice";
      EXPECT_EQ(parts[i].first.find("/msg/"), std::string::npos) << "MSG: names are pkg/Type";
    }
    for (std::size_t i = 0; i < parts.size(); ++i) {
      const std::string package = i == 0 ? type.substr(0, type.find('/')) : parts[i].first.substr(0, parts[i].first.find('/'));
      for (const std::string& line : parts[i].second) {
        std::string field_type = line.substr(0, line.find(' '));
        if (line.find('=') != std::string::npos && line.find(' ') < line.find('=')) {
          // a constant ("int32 ARROW=0"): a builtin type
          EXPECT_TRUE(builtin.count(field_type)) << line;
          continue;
        }
        field_type = field_type.substr(0, field_type.find('['));
        if (builtin.count(field_type)) continue;
        const std::string qualified = field_type.find('/') == std::string::npos ? package + "/" + field_type : field_type;
        EXPECT_TRUE(names.count(qualified)) << type << ": no section for " << qualified << " (" << line << ")";
      }
    }
  }
}

TEST(MessageSchemas, TypeNamesOfTheStructsAreKnown) {
  for (const char* name : {msg::Image::kTypeName, msg::CompressedImage::kTypeName, msg::CameraInfo::kTypeName,
                           msg::PointCloud2::kTypeName, msg::TFMessage::kTypeName, msg::Marker::kTypeName,
                           msg::MarkerArray::kTypeName, msg::String::kTypeName, msg::TransformStamped::kTypeName,
                           msg::Pose::kTypeName})
    EXPECT_FALSE(ros2msg_definition(name).empty()) << name;
}

TEST(MessageSchemas, MarkerIsTheHumbleDefinition) {
  const std::string marker = ros2msg_schema(msg::Marker::kTypeName);
  for (const char* field : {"string texture_resource\n", "sensor_msgs/CompressedImage texture\n",
                            "UVCoordinate[] uv_coordinates\n", "MeshFile mesh_file\n",
                            "bool mesh_use_embedded_materials\n", "MSG: visualization_msgs/UVCoordinate\n",
                            "MSG: sensor_msgs/CompressedImage\n", "MSG: builtin_interfaces/Duration\n"})
    EXPECT_NE(marker.find(field), std::string::npos) << field;
}

TEST(MessageSchemas, AnUnknownTypeIsInputError) {
  // Named, with the types canopy knows.
  test::expect_input_error([] { ros2msg_schema("sensor_msgs/msg/Imu"); },
                           "no ros2msg schema for message type 'sensor_msgs/msg/Imu' (canopy knows builtin_interfaces");
  EXPECT_TRUE(ros2msg_definition("nope/msg/Nope").empty());
}

}  // namespace
}  // namespace canopy::ros2
