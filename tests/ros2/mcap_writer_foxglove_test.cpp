// canopy's recordings read by Foxglove's reader (@mcap/core's indexed and streaming readers,
// @foxglove/rosmsg2-serialization decoding each message from its ros2msg schema): with every
// compression, every message type is found with its size, encoding, stamps and values, the tf
// tree is whole, and Foxglove encodes each decoded message back to canopy's bytes exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "canopy/ros2/mcap_writer.h"
#include "foxglove_reference.h"

namespace canopy::ros2 {
namespace {

using namespace test;
using nlohmann::json;

void expect_bytes(const json& j, const std::vector<std::uint8_t>& b) {
  EXPECT_EQ(j.at("bytes").get<std::size_t>(), b.size());
  EXPECT_EQ(j.at("crc32").get<std::uint32_t>(), crc32_of(b));
}

void expect_image(const json& j, const msg::Image& m) {
  expect_header(j.at("header"), m.header);
  EXPECT_EQ(j.at("height").get<std::uint32_t>(), m.height);
  EXPECT_EQ(j.at("width").get<std::uint32_t>(), m.width);
  EXPECT_EQ(j.at("encoding").get<std::string>(), m.encoding);
  EXPECT_EQ(j.at("step").get<std::uint32_t>(), m.step);
  EXPECT_EQ(j.at("is_bigendian").get<int>(), m.is_bigendian);
  expect_bytes(j.at("data"), m.data);
}

void expect_camera_info(const json& j, const msg::CameraInfo& m) {
  expect_header(j.at("header"), m.header);
  EXPECT_EQ(j.at("width").get<std::uint32_t>(), m.width);
  EXPECT_EQ(j.at("height").get<std::uint32_t>(), m.height);
  EXPECT_EQ(j.at("distortion_model").get<std::string>(), m.distortion_model);
  expect_numbers(j.at("d"), m.d);
  expect_numbers(j.at("k"), m.k);
  expect_numbers(j.at("r"), m.r);
  expect_numbers(j.at("p"), m.p);
  EXPECT_EQ(j.at("binning_y").get<std::uint32_t>(), m.binning_y);
  EXPECT_EQ(j.at("roi").at("width").get<std::uint32_t>(), m.roi.width);
  EXPECT_EQ(j.at("roi").at("do_rectify").get<bool>(), m.roi.do_rectify);
}

void expect_transform(const json& j, const msg::TransformStamped& t) {
  expect_header(j.at("header"), t.header);
  EXPECT_EQ(j.at("child_frame_id").get<std::string>(), t.child_frame_id);
  const json& tr = j.at("transform");
  EXPECT_EQ(tr.at("translation").at("x").get<double>(), t.transform.translation.x);
  EXPECT_EQ(tr.at("translation").at("z").get<double>(), t.transform.translation.z);
  EXPECT_EQ(tr.at("rotation").at("z").get<double>(), t.transform.rotation.z);
  EXPECT_EQ(tr.at("rotation").at("w").get<double>(), t.transform.rotation.w);
}

void expect_cloud(const json& j, const msg::PointCloud2& m) {
  expect_header(j.at("header"), m.header);
  ASSERT_EQ(j.at("fields").size(), m.fields.size());
  for (std::size_t i = 0; i < m.fields.size(); ++i) {
    EXPECT_EQ(j["fields"][i].at("name").get<std::string>(), m.fields[i].name);
    EXPECT_EQ(j["fields"][i].at("offset").get<std::uint32_t>(), m.fields[i].offset);
    EXPECT_EQ(j["fields"][i].at("datatype").get<int>(), m.fields[i].datatype);
  }
  EXPECT_EQ(j.at("point_step").get<std::uint32_t>(), m.point_step);
  EXPECT_EQ(j.at("width").get<std::uint32_t>(), m.width);
  EXPECT_EQ(j.at("is_dense").get<bool>(), m.is_dense);
  expect_bytes(j.at("data"), m.data);
}

void expect_markers(const json& j, const msg::MarkerArray& a) {
  ASSERT_EQ(j.at("markers").size(), a.markers.size());
  for (std::size_t i = 0; i < a.markers.size(); ++i) {
    const json& mj = j["markers"][i];
    const msg::Marker& m = a.markers[i];
    expect_header(mj.at("header"), m.header);
    EXPECT_EQ(mj.at("ns").get<std::string>(), m.ns);
    EXPECT_EQ(mj.at("id").get<int>(), m.id);
    EXPECT_EQ(mj.at("type").get<int>(), m.type);
    EXPECT_EQ(mj.at("scale").at("x").get<double>(), m.scale.x);
    EXPECT_EQ(mj.at("color").at("g").get<double>(), double(m.color.g));
    EXPECT_EQ(mj.at("lifetime").at("sec").get<int>(), m.lifetime.sec);
    EXPECT_EQ(mj.at("frame_locked").get<bool>(), m.frame_locked);
    EXPECT_EQ(mj.at("points").size(), m.points.size());
    EXPECT_EQ(mj.at("colors").size(), m.colors.size());
    EXPECT_EQ(mj.at("texture_resource").get<std::string>(), m.texture_resource);
    EXPECT_EQ(mj.at("texture").at("format").get<std::string>(), m.texture.format);
    expect_bytes(mj.at("texture").at("data"), m.texture.data);
    EXPECT_EQ(mj.at("uv_coordinates").size(), m.uv_coordinates.size());
    EXPECT_EQ(mj.at("text").get<std::string>(), m.text);
    EXPECT_EQ(mj.at("mesh_file").at("filename").get<std::string>(), m.mesh_file.filename);
    expect_bytes(mj.at("mesh_file").at("data"), m.mesh_file.data);
    EXPECT_EQ(mj.at("mesh_use_embedded_materials").get<bool>(), m.mesh_use_embedded_materials);
  }
}

TEST(McapWriterFoxglove, FoxgloveReadsEveryMessageWithEveryCompression) {
  for (Compression c : {Compression::kNone, Compression::kLz4, Compression::kZstd}) {
    const std::string name = c == Compression::kNone ? "none" : std::string(compression_name(c));
    SCOPED_TRACE(name);
    McapWriterOptions options;
    options.compression = c;
    options.chunk_size_bytes = 30000;  // several chunks
    const std::string path = temp_path("canopy_" + name + ".mcap");
    const std::vector<Written> written = write_sample_recording(path, options, 6, 64, 48);
    const std::string out = temp_path("dump_" + name + ".json");
    ASSERT_TRUE(run_foxglove({"dump", path, out}));
    const json dump = read_json(out);

    EXPECT_EQ(dump.at("header").at("profile"), "ros2");
    EXPECT_EQ(dump.at("header").at("library"), mcap_library_name());
    EXPECT_EQ(dump.at("chunk_compressions"), json::array({std::string(compression_name(c))}));
    EXPECT_GE(dump.at("chunk_count").get<int>(), 3);
    EXPECT_EQ(dump.at("statistics").at("messageCount"), std::to_string(written.size()));
    EXPECT_EQ(dump.at("stream_record_counts").at("Message").get<std::size_t>(), written.size());
    EXPECT_EQ(dump.at("stream_record_counts").at("ChunkIndex"), dump.at("chunk_count"));
    EXPECT_EQ(dump.at("stream_record_counts").at("Footer"), 1);
    ASSERT_EQ(dump.at("channels").size(), 10u);
    for (const json& ch : dump.at("channels")) {
      EXPECT_EQ(ch.at("schema_encoding"), "ros2msg");
      EXPECT_EQ(ch.at("message_encoding"), "cdr");
    }

    // Foxglove delivers log-time order, ties in file order: the written messages sorted so.
    std::vector<Written> sorted = written;
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const Written& a, const Written& b) { return a.log_time_ns < b.log_time_ns; });
    const json& messages = dump.at("messages");
    ASSERT_EQ(messages.size(), sorted.size());
    std::map<std::string, std::pair<std::string, msg::Transform>> parent_of;  // the tf tree
    for (std::size_t i = 0; i < sorted.size(); ++i) {
      SCOPED_TRACE(sorted[i].topic + " #" + std::to_string(i));
      const json& m = messages[i];
      const Written& w = sorted[i];
      EXPECT_EQ(m.at("topic").get<std::string>(), w.topic);
      EXPECT_EQ(m.at("schema").get<std::string>(), w.type);
      EXPECT_EQ(m.at("log_time").get<std::string>(), std::to_string(w.log_time_ns));
      EXPECT_EQ(m.at("size").get<std::size_t>(), w.data.size());
      EXPECT_TRUE(m.at("reencoded_equal").get<bool>()) << "Foxglove's encoding of the decoded message differs";
      const json& v = m.at("value");
      if (w.type == msg::Image::kTypeName) {
        expect_image(v, deserialize<msg::Image>(w.data));
      } else if (w.type == msg::CameraInfo::kTypeName) {
        expect_camera_info(v, deserialize<msg::CameraInfo>(w.data));
      } else if (w.type == msg::TFMessage::kTypeName) {
        const msg::TFMessage tf = deserialize<msg::TFMessage>(w.data);
        ASSERT_EQ(v.at("transforms").size(), tf.transforms.size());
        for (std::size_t k = 0; k < tf.transforms.size(); ++k) {
          expect_transform(v["transforms"][k], tf.transforms[k]);
          const json& t = v["transforms"][k];
          msg::Transform tr;
          tr.translation.x = t["transform"]["translation"]["x"].get<double>();
          parent_of[t["child_frame_id"].get<std::string>()] = {t["header"]["frame_id"].get<std::string>(), tr};
        }
      } else if (w.type == msg::CompressedImage::kTypeName) {
        const auto ci = deserialize<msg::CompressedImage>(w.data);
        expect_header(v.at("header"), ci.header);
        EXPECT_EQ(v.at("format").get<std::string>(), "png");
        expect_bytes(v.at("data"), ci.data);
      } else if (w.type == msg::PointCloud2::kTypeName) {
        expect_cloud(v, deserialize<msg::PointCloud2>(w.data));
      } else if (w.type == msg::MarkerArray::kTypeName) {
        expect_markers(v, deserialize<msg::MarkerArray>(w.data));
      } else if (w.type == msg::String::kTypeName) {
        EXPECT_EQ(v.at("data").get<std::string>(), mcap_library_name());
      } else {
        ADD_FAILURE() << "unexpected type " << w.type;
      }
    }
    // The tf tree Foxglove sees: the optical frame up to the world through the arm.
    std::vector<std::string> chain;
    for (std::string f = "camera_color_optical_frame"; parent_of.count(f) && chain.size() < 10; f = parent_of[f].first)
      chain.push_back(parent_of[f].first);
    EXPECT_EQ(chain, (std::vector<std::string>{"camera_link", "tool0", "base_link", "world"}));
    EXPECT_EQ(parent_of["camera_link"].second.translation.x, 0.05);
  }
}

}  // namespace
}  // namespace canopy::ros2
