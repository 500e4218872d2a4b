#pragma once
// The `ros2msg` schema texts of the messages in messages.h, as rosbag2 writes them into MCAP
// Schema records and Foxglove reads them: the type's .msg definition (ROS 2 Humble), then for
// each type it uses, directly or not, a line of 80 '=', a line `MSG: pkg/Type` and that type's
// definition.

#include <string>
#include <string_view>
#include <vector>

namespace canopy::ros2 {

/// The MCAP schema encoding of ROS 2 message definitions.
constexpr const char* kRos2MsgSchemaEncoding = "ros2msg";
/// The MCAP message encoding of ROS 2 messages.
constexpr const char* kCdrMessageEncoding = "cdr";

/// The ros2msg text of `type_name` ("sensor_msgs/msg/Image"), dependencies included. Throws
/// InputError for a type canopy does not know (known_message_types() lists them).
std::string ros2msg_schema(std::string_view type_name);
/// The definition of `type_name` alone, without its dependencies ("" for an unknown type).
std::string_view ros2msg_definition(std::string_view type_name);
/// The message types with a schema here, "pkg/msg/Type".
std::vector<std::string> known_message_types();

}  // namespace canopy::ros2
