#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "canopy/common/camera.h"
#include "canopy/common/classes.h"
#include "canopy/common/error.h"
#include "canopy/common/io.h"
#include "canopy/common/robot_config.h"
#include "canopy/common/yaml_reader.h"

namespace canopy {
namespace {

TEST(Camera, ProjectUnprojectRoundTripAndConvention) {
  CameraIntrinsics K;
  // x right, y down, z forward: a point right of and below the axis lands right and below
  // the image centre.
  double u = 0, v = 0;
  ASSERT_TRUE(K.project(Vec3(0.1, 0.05, 1.0), &u, &v));
  EXPECT_GT(u, K.cx_px);
  EXPECT_GT(v, K.cy_px);
  const Vec3 p = K.unproject(u, v, 1.0);
  EXPECT_NEAR((p - Vec3(0.1, 0.05, 1.0)).norm(), 0.0, 1e-12);
  EXPECT_FALSE(K.project(Vec3(0, 0, -1), &u, &v));
  EXPECT_NEAR(K.fovy_deg(), 2.0 * std::atan(200.0 / 381.36) * 180.0 / M_PI, 1e-12);
}

TEST(Camera, ValidateRejectsBadValues) {
  CameraIntrinsics K;
  EXPECT_NO_THROW(K.validate("x.yaml"));
  K.fx_px = 0.0;
  EXPECT_THROW(K.validate("x.yaml"), InputError);
  K = CameraIntrinsics();
  K.max_range_m = 0.05;
  EXPECT_THROW(K.validate("x.yaml"), InputError);
}

TEST(YamlReader, UnknownKeysAndTypesAreNamed) {
  YamlReader y = YamlReader::load_string("a: 1\nb: two\nc: {d: 3}\n", "t.yaml");
  EXPECT_EQ(y.get("a", 0), 1);
  try {
    y.require<double>("b");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.yaml: key 'b': value 'two'"), std::string::npos) << e.what();
  }
  YamlReader c = y.child("c");
  EXPECT_THROW(c.finish(), InputError);  // d not read
  EXPECT_EQ(c.get("d", 0), 3);
  EXPECT_NO_THROW(c.finish());
  EXPECT_NO_THROW(y.finish());
  YamlReader z = YamlReader::load_string("a: 1\nzz: 2\n", "t.yaml");
  z.get("a", 0);
  try {
    z.finish();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'zz'"), std::string::npos);
  }
  EXPECT_THROW(YamlReader::load_string("a: [1, 2\n", "bad.yaml"), InputError);
  EXPECT_THROW(YamlReader::load_file("/nonexistent.yaml"), InputError);
}

TEST(Io, PngRoundTrips) {
  const std::string dir = testing::TempDir();
  Image<Rgb8> rgb(5, 3);
  Image<std::uint16_t> g(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      rgb.at(x, y) = Rgb8{static_cast<std::uint8_t>(x * 40), static_cast<std::uint8_t>(y * 70), 9};
      g.at(x, y) = static_cast<std::uint16_t>(x * 1000 + y * 17 + 60000 * (x == 4));
    }
  write_png(dir + "/a.png", rgb);
  write_png_gray16(dir + "/b.png", g);
  EXPECT_EQ(read_png_rgb(dir + "/a.png").data, rgb.data);
  EXPECT_EQ(read_png_gray16(dir + "/b.png").data, g.data);
  write_file_atomic(dir + "/c.png", "not a png");
  EXPECT_THROW(read_png_rgb(dir + "/c.png"), InputError);
}

TEST(Io, ParsesPosesAndRejectsBadOnes) {
  const Pose T = parse_pose7("1,2,3,1,0,0,0", "--camera-pose");
  EXPECT_NEAR((T.translation() - Vec3(1, 2, 3)).norm(), 0, 1e-12);
  EXPECT_THROW(parse_pose7("1,2,3,1,1,0,0", "--camera-pose"), InputError);  // not unit
  EXPECT_THROW(parse_pose7("1,2,3", "--camera-pose"), InputError);
  EXPECT_THROW(parse_numbers("1,nan,3", 3, "--base"), InputError);
  EXPECT_THROW(parse_numbers("1,x,3", 3, "--base"), InputError);
  const Pose back = pose_from_json(pose_to_json(T));
  EXPECT_LT((back.matrix() - T.matrix()).norm(), 1e-12);
}

TEST(Io, StagedDirOnlyAppearsOnCommit) {
  namespace fs = std::filesystem;
  const std::string out = testing::TempDir() + "/staged_out";
  fs::remove_all(out);
  {
    StagedDir d(out);
    write_file_atomic(d.path("x.txt"), "x");
  }  // no commit: nothing left
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));
  StagedDir d(out);
  write_file_atomic(d.path("x.txt"), "x");
  d.commit();
  EXPECT_TRUE(fs::exists(out + "/x.txt"));
  // A second run may replace canopy's own output...
  {
    StagedDir again(out);
    write_file_atomic(again.path("y.txt"), "y");
    again.commit();
  }
  EXPECT_TRUE(fs::exists(out + "/y.txt"));
  EXPECT_FALSE(fs::exists(out + "/x.txt"));
  // ...but never a folder canopy did not write.
  const std::string foreign = testing::TempDir() + "/foreign_folder";
  fs::create_directories(foreign);
  write_file_atomic(foreign + "/precious.txt", "keep me");
  EXPECT_THROW(StagedDir{foreign}, InputError);
  EXPECT_TRUE(fs::exists(foreign + "/precious.txt"));
}

TEST(Classes, ValidateAndColors) {
  SemanticClasses c;
  EXPECT_NO_THROW(c.validate("w.yaml"));
  EXPECT_EQ(c.target_index(), 2);
  EXPECT_EQ(c.color(0), (Rgb8{0, 0, 0}));
  c.names = {"leaf", "fruit"};
  EXPECT_THROW(c.validate("w.yaml"), InputError);
  c.names = {"background", "fruit", "fruit"};
  EXPECT_THROW(c.validate("w.yaml"), InputError);
  c.names = {"background", "a", "b", "c", "d", "e", "f", "fruit"};  // 8 > kMaxClasses
  EXPECT_THROW(c.validate("w.yaml"), InputError);
  c.names.pop_back();
  c.names.back() = "fruit";
  EXPECT_NO_THROW(c.validate("w.yaml"));
}

TEST(RobotConfig, DefaultsEqualTheShippedYaml) {
  const RobotConfig file = default_robot_config();
  const RobotConfig defaults;
  EXPECT_EQ(file.home, defaults.home);
  EXPECT_EQ(file.arm_kp, defaults.arm_kp);
  EXPECT_EQ(file.arm_joints, defaults.arm_joints);
  EXPECT_EQ(file.base_kv, defaults.base_kv);
  EXPECT_EQ(file.arm_max_velocity, defaults.arm_max_velocity);
}

}  // namespace
}  // namespace canopy

namespace canopy {
namespace {

TEST(Camera, LookAtHasZeroRollAndLooksAtTheTarget) {
  const Vec3 eye(0.3, -0.2, 1.0), target(1.0, 0.5, 0.6);
  const Pose T = look_at(eye, target);
  EXPECT_LT((T.linear().transpose() * T.linear() - Mat3::Identity()).norm(), 1e-12);
  EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);
  // The target projects to the image centre, image x is horizontal, image up is world up.
  CameraIntrinsics K;
  double u = 0, v = 0;
  ASSERT_TRUE(K.project(T.inverse() * target, &u, &v));
  EXPECT_NEAR(u, K.cx_px, 1e-9);
  EXPECT_NEAR(v, K.cy_px, 1e-9);
  EXPECT_NEAR(T.linear().col(0).z(), 0.0, 1e-12);
  EXPECT_LT(T.linear().col(1).z(), 0.0);
  // Straight down is still a valid rotation.
  const Pose D = look_at(Vec3(0, 0, 1), Vec3(0, 0, 0));
  EXPECT_NEAR(D.linear().determinant(), 1.0, 1e-12);
}

}  // namespace
}  // namespace canopy
