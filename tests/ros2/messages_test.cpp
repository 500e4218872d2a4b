// ROS 2 messages: every type encodes and decodes back to the same bytes, and a message cut at
// any byte is refused with InputError.
#include "canopy/ros2/messages.h"

#include <gtest/gtest.h>

#include "sample_messages.h"

namespace canopy::ros2 {
namespace {

using namespace test;

// Decoding then encoding again gives the same bytes: no field is lost or moved.
template <class M>
void expect_round_trip(const M& m) {
  const std::string bytes = serialize(m);
  EXPECT_EQ(serialize(deserialize<M>(bytes)), bytes) << M::kTypeName;
}

// Every proper prefix of the message is refused (never read past the end, never a crash).
template <class M>
void expect_every_cut_refused(const M& m, std::size_t stride = 1) {
  const std::string bytes = serialize(m);
  for (std::size_t n = 0; n < bytes.size(); n += stride) {
    EXPECT_THROW(deserialize<M>(std::string_view(bytes).substr(0, n)), InputError) << M::kTypeName << " cut at " << n;
  }
}

TEST(Messages, EveryTypeRoundTrips) {
  expect_round_trip(msg::Time::from_ns(1700000000123456789ull));
  expect_round_trip(msg::Duration{3, 4});
  expect_round_trip(sample_header(5, "cam"));
  expect_round_trip(msg::String{"canopy 0.2.0"});
  expect_round_trip(msg::ColorRGBA{0.1f, 0.2f, 0.3f, 0.4f});
  expect_round_trip(msg::Vector3{1, 2, 3});
  expect_round_trip(msg::Point{4, 5, 6});
  expect_round_trip(msg::Quaternion{0, 0, 0.6, 0.8});
  expect_round_trip(msg::Pose{{1, 2, 3}, {0, 0, 0, 1}});
  expect_round_trip(sample_transform(7, "a", "b", 0.5));
  expect_round_trip(sample_tf(8, 0.25));
  expect_round_trip(sample_rgb(5, 3, 9, 1));
  expect_round_trip(sample_depth32(5, 3, 9, 1));
  expect_round_trip(sample_depth16(5, 3, 9));
  expect_round_trip(sample_compressed(10));
  expect_round_trip(sample_camera_info(11));
  expect_round_trip(sample_cloud(12, 10));
  expect_round_trip(sample_markers(13));
}

TEST(Messages, DecodedFieldsEqualTheWrittenOnes) {
  const msg::CameraInfo info = deserialize<msg::CameraInfo>(serialize(sample_camera_info(11)));
  EXPECT_EQ(info.header.frame_id, "camera_color_optical_frame");
  EXPECT_EQ(info.width, 640u);
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  EXPECT_EQ(info.d.size(), 5u);
  EXPECT_DOUBLE_EQ(info.k[2], 320.25);
  EXPECT_DOUBLE_EQ(info.p[6], 240.5);
  EXPECT_EQ(info.binning_y, 2u);
  EXPECT_TRUE(info.roi.do_rectify);
  EXPECT_EQ(info.roi.width, 600u);

  const msg::TFMessage tf = deserialize<msg::TFMessage>(serialize(sample_tf(8, 0.25)));
  ASSERT_EQ(tf.transforms.size(), 2u);
  EXPECT_EQ(tf.transforms[1].header.frame_id, "base_link");
  EXPECT_EQ(tf.transforms[1].child_frame_id, "tool0");
  EXPECT_DOUBLE_EQ(tf.transforms[1].transform.translation.x, 0.125);

  const msg::MarkerArray markers = deserialize<msg::MarkerArray>(serialize(sample_markers(13)));
  ASSERT_EQ(markers.markers.size(), 2u);
  EXPECT_EQ(markers.markers[0].texture.format, "png");
  EXPECT_EQ(markers.markers[0].mesh_file.filename, "pepper.stl");
  EXPECT_TRUE(markers.markers[0].mesh_use_embedded_materials);
  EXPECT_EQ(markers.markers[1].text, "fruit 3");
}

TEST(Messages, TimeSplitsNanoseconds) {
  const msg::Time t = msg::Time::from_ns(1700000000123456789ull);
  EXPECT_EQ(t.sec, 1700000000);
  EXPECT_EQ(t.nanosec, 123456789u);
  EXPECT_EQ(t.to_ns(), 1700000000123456789ull);
  EXPECT_EQ((msg::Time{-1, 5}.to_ns()), 0u);
}

TEST(Messages, QuaternionDefaultsToIdentity) {
  EXPECT_EQ(msg::Quaternion{}.w, 1.0);
  EXPECT_EQ(msg::Transform{}.rotation.w, 1.0);
}

TEST(Messages, EveryCutIsRefused) {
  expect_every_cut_refused(sample_header(5, "cam"));
  expect_every_cut_refused(sample_tf(8, 0.25));
  expect_every_cut_refused(sample_camera_info(11));
  expect_every_cut_refused(sample_compressed(10));
  expect_every_cut_refused(sample_rgb(5, 3, 9, 1));
  expect_every_cut_refused(sample_cloud(12, 3));
  expect_every_cut_refused(sample_markers(13));
}

}  // namespace
}  // namespace canopy::ros2
