// Recordings written by Foxglove's writer (@mcap/core's McapWriter, ros2 profile, messages
// encoded by @foxglove/rosmsg2-serialization from Humble definitions written independently of
// canopy's) read by McapReader: LZ4 and zstd chunks and a file without chunks, 16UC1 and 32FC1
// depth, a PNG CompressedImage, CameraInfo, /tf and /tf_static, with the values written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "canopy/ros2/mcap_reader.h"
#include "foxglove_reference.h"

namespace canopy::ros2 {
namespace {

using namespace test;
using nlohmann::json;

std::vector<std::uint8_t> as_bytes(const std::string& s) { return std::vector<std::uint8_t>(s.begin(), s.end()); }

TEST(McapReaderFoxglove, ReadsFoxglovesRecordings) {
  const std::string dir = temp_path("foxglove");
  std::filesystem::create_directories(dir);
  ASSERT_TRUE(run_foxglove({"write", dir}));
  const json expected = read_json(dir + "/foxglove_expected.json");
  const json& messages = expected.at("messages");
  ASSERT_EQ(messages.size(), 26u);

  // What the reader should deliver: log-time order, ties in the order written.
  std::vector<std::size_t> order(messages.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::stoull(messages[a].at("log_time").get<std::string>()) <
           std::stoull(messages[b].at("log_time").get<std::string>());
  });

  for (const std::string kind : {"lz4", "zstd", "plain"}) {
    SCOPED_TRACE(kind);
    McapReader in(dir + "/foxglove_" + kind + ".mcap");
    in.verify();
    EXPECT_EQ(in.library(), "foxglove-reference (@mcap/core 2.2.2)");
    EXPECT_EQ(in.indexed(), kind != "plain");  // without chunks there is no chunk index: a scan
    EXPECT_EQ(in.message_count(), messages.size());
    EXPECT_EQ(in.channels().count(0), 1u) << "Foxglove numbers channels from 0";
    EXPECT_EQ(in.topics().size(), 6u);

    std::size_t n = 0;
    in.for_each_message([&](const McapMessage& m) -> bool {
      if (n >= order.size()) return false;
      const json& e = messages[order[n++]];
      SCOPED_TRACE(e.at("topic").get<std::string>() + " at " + e.at("log_time").get<std::string>());
      EXPECT_EQ(m.channel->topic, e.at("topic").get<std::string>());
      EXPECT_EQ(m.schema->name, e.at("schema").get<std::string>());
      EXPECT_EQ(std::to_string(m.log_time_ns), e.at("log_time").get<std::string>());
      EXPECT_TRUE(std::string(m.data) == base64_decode(e.at("cdr_base64").get<std::string>())) << "the CDR bytes";
      const json& v = e.at("value");
      const std::string& type = m.schema->name;
      if (type == msg::Image::kTypeName) {
        const msg::Image image = in.decode<msg::Image>(m);
        expect_header(v.at("header"), image.header);
        EXPECT_EQ(image.encoding, v.at("encoding").get<std::string>());
        EXPECT_EQ(image.width, 8u);
        EXPECT_EQ(image.height, 6u);
        EXPECT_EQ(image.data, as_bytes(base64_decode(e.at("data_base64").get<std::string>())));
        if (image.encoding == "16UC1") {
          EXPECT_EQ(image.step, 16u);
          std::uint16_t mm[2];
          std::memcpy(mm, image.data.data(), 4);
          EXPECT_EQ(mm[0], 0) << "no return";
          EXPECT_GE(mm[1], 400);
        } else {
          EXPECT_EQ(image.encoding, "32FC1");
          EXPECT_EQ(image.step, 32u);
          float metres[2];
          std::memcpy(metres, image.data.data(), 8);
          EXPECT_TRUE(std::isnan(metres[0])) << "no return";
          EXPECT_NEAR(metres[1], 0.41, 0.01);
        }
      } else if (type == msg::CompressedImage::kTypeName) {
        const auto image = in.decode<msg::CompressedImage>(m);
        expect_header(v.at("header"), image.header);
        EXPECT_EQ(image.format, "png");
        EXPECT_TRUE(image.data.size() >= 8 && image.data[1] == 'P') << "a PNG";
        EXPECT_EQ(image.data, as_bytes(base64_decode(e.at("data_base64").get<std::string>())));
      } else if (type == msg::CameraInfo::kTypeName) {
        const auto info = in.decode<msg::CameraInfo>(m);
        expect_header(v.at("header"), info.header);
        EXPECT_EQ(info.distortion_model, "plumb_bob");
        EXPECT_EQ(info.width, 8u);
        expect_numbers(v.at("d"), info.d);
        expect_numbers(v.at("k"), info.k);
        expect_numbers(v.at("r"), info.r);
        expect_numbers(v.at("p"), info.p);
        EXPECT_EQ(info.roi.x_offset, 1u);
        EXPECT_EQ(info.roi.width, 4u);
        EXPECT_FALSE(info.roi.do_rectify);
      } else if (type == msg::TFMessage::kTypeName) {
        const auto tf = in.decode<msg::TFMessage>(m);
        EXPECT_EQ(tf.transforms.size(), v.at("transforms").size());
        for (std::size_t k = 0; k < std::min(tf.transforms.size(), v.at("transforms").size()); ++k) {
          const json& t = v["transforms"][k];
          const msg::TransformStamped& s = tf.transforms[k];
          expect_header(t.at("header"), s.header);
          EXPECT_EQ(s.child_frame_id, t.at("child_frame_id").get<std::string>());
          const json& tr = t.at("transform");
          EXPECT_EQ(s.transform.translation.x, tr["translation"]["x"].get<double>());
          EXPECT_EQ(s.transform.translation.y, tr["translation"]["y"].get<double>());
          EXPECT_EQ(s.transform.rotation.z, tr["rotation"]["z"].get<double>());
          EXPECT_EQ(s.transform.rotation.w, tr["rotation"]["w"].get<double>());
        }
        if (m.channel->topic == "/tf_static" && tf.transforms.size() == 2) {
          EXPECT_EQ(tf.transforms[1].child_frame_id, "camera_color_optical_frame");
          EXPECT_NEAR(tf.transforms[1].transform.rotation.z, -std::sqrt(0.5), 1e-12);
        }
      } else {
        ADD_FAILURE() << "unexpected type " << type;
      }
      return true;
    });
    EXPECT_EQ(n, messages.size());
  }
}

}  // namespace
}  // namespace canopy::ros2
