// The transform tree of a recording: static and timed edges composed along the tree, a sample
// taken as is at its stamp, two samples interpolated (position linearly, rotation by slerp, as
// tf2), the ends reached within the tolerance only, and what is refused (a second parent, a
// rotation that is no unit quaternion, frames in separate trees).

#include <gtest/gtest.h>

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/ros2/tf_buffer.h"

namespace canopy::ros2 {
namespace {

msg::TransformStamped edge(const std::string& parent, const std::string& child, std::int64_t ns, const Vec3& p,
                           double yaw) {
  msg::TransformStamped t;
  t.header.stamp = msg::Time::from_ns(std::uint64_t(ns));
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation = {p.x(), p.y(), p.z()};
  t.transform.rotation = {0.0, 0.0, std::sin(yaw / 2), std::cos(yaw / 2)};
  return t;
}

double yaw_of(const Pose& T) { return std::atan2(T.linear()(1, 0), T.linear()(0, 0)); }

constexpr std::int64_t kS = 1000000000;

TfBuffer lab_tree() {
  TfBuffer tf;
  // map -> odom static, odom -> base_link at 1 s and 2 s, base_link -> camera static.
  tf.add({{edge("map", "odom", 0, Vec3(10, 0, 0), 0.0)}}, true, "test");
  tf.add({{edge("odom", "base_link", 1 * kS, Vec3(0, 0, 0), 0.0)}}, false, "test");
  tf.add({{edge("odom", "base_link", 2 * kS, Vec3(2, 0, 0), M_PI / 2)}}, false, "test");
  tf.add({{edge("base_link", "camera", 0, Vec3(0, 0, 1), 0.0)}}, true, "test");
  return tf;
}

TEST(TfBuffer, ComposesAndInterpolatesAsTf2Does) {
  const TfBuffer tf = lab_tree();
  EXPECT_EQ(tf.root_of("camera"), "map");
  std::string why;
  const auto at = [&](std::int64_t ns) { return tf.lookup("map", "camera", ns, kS / 50, &why); };
  const auto exact = at(2 * kS);
  ASSERT_TRUE(exact);
  EXPECT_TRUE(exact->translation().isApprox(Vec3(12, 0, 1)));
  EXPECT_NEAR(yaw_of(*exact), M_PI / 2, 1e-12);
  const auto half = at(3 * kS / 2);  // half-way: 1 m along, 45 degrees
  ASSERT_TRUE(half);
  EXPECT_TRUE(half->translation().isApprox(Vec3(11, 0, 1)));
  EXPECT_NEAR(yaw_of(*half), M_PI / 4, 1e-12);
  EXPECT_TRUE(at(2 * kS + kS / 100));  // within the tolerance past the last sample
  EXPECT_FALSE(at(2 * kS + kS / 10));
  EXPECT_NE(why.find("the transform odom -> base_link has no sample within max_dt of 2.100000000 s"), std::string::npos)
      << why;
  // The inverse direction, and a lookup between two frames below the root.
  const auto inv = tf.lookup("camera", "map", 2 * kS, 0, &why);
  ASSERT_TRUE(inv);
  EXPECT_TRUE((*inv * *exact).isApprox(Pose::Identity()));
  const auto rel = tf.lookup("base_link", "camera", 3 * kS / 2, 0, &why);
  ASSERT_TRUE(rel);
  EXPECT_TRUE(rel->translation().isApprox(Vec3(0, 0, 1)));
}

TEST(TfBuffer, SamplesOutOfOrderAreSorted) {
  TfBuffer tf;
  tf.add({{edge("odom", "base", 2 * kS, Vec3(2, 0, 0), 0)}}, false, "t");
  tf.add({{edge("odom", "base", 0, Vec3(0, 0, 0), 0)}}, false, "t");
  std::string why;
  const auto T = tf.lookup("odom", "base", kS, 0, &why);
  ASSERT_TRUE(T) << why;
  EXPECT_TRUE(T->translation().isApprox(Vec3(1, 0, 0)));
}

TEST(TfBuffer, RefusesTwoParentsARotationThatIsNoQuaternionAndSeparateTrees) {
  TfBuffer tf = lab_tree();
  try {
    tf.add({{edge("map", "base_link", 0, Vec3::Zero(), 0)}}, false, "rec.mcap: /tf at 1 s");
    FAIL() << "a second parent accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "rec.mcap: /tf at 1 s: the frame 'base_link' has two parents, 'odom' and 'map'");
  }
  msg::TransformStamped scaled = edge("a", "b", 0, Vec3::Zero(), 0);
  scaled.transform.rotation.w = 2.0;
  EXPECT_THROW(tf.add({{scaled}}, false, "x"), InputError);
  tf.add({{edge("other", "thing", 0, Vec3::Zero(), 0)}}, true, "x");
  std::string why;
  EXPECT_FALSE(tf.lookup("map", "thing", 0, kS, &why));
  EXPECT_NE(why.find("a transform between the trees is missing"), std::string::npos) << why;
}

}  // namespace
}  // namespace canopy::ros2
