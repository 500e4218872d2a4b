#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "canopy/common/camera.h"
#include "canopy/common/classes.h"
#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/read_file.h"
#include "canopy/robot/robot_config.h"
#include "canopy/common/yaml_reader.h"

namespace canopy {
namespace {

TEST(TestSupport, EachTestProcessHasItsOwnTempDir) {
  // ctest -j2 runs two test processes at once; fixed file names under TempDir() must not meet.
  const std::filesystem::path d = testing::TempDir();
  EXPECT_TRUE(std::filesystem::is_directory(d)) << d;
  EXPECT_NE(d.string().find("canopy_test_"), std::string::npos) << d;
  EXPECT_NE(std::filesystem::canonical(d), std::filesystem::canonical(std::filesystem::temp_directory_path()));
}

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

// Nested aliases that expand to billions of nodes are refused while parsing, in linear time.
TEST(YamlReader, AliasBombsAndEmptyFilesAreRefused) {
  std::string bomb = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i <= 9; ++i) {
    bomb += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k) bomb += std::string(k ? ", " : "") + "*a" + std::to_string(i - 1);
    bomb += "]\n";
  }
  try {
    YamlReader::load_string(bomb, "bomb.yaml");
    FAIL() << "an alias bomb was parsed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("expands to more than"), std::string::npos) << e.what();
  }
  // A few aliases are fine.
  EXPECT_NO_THROW(YamlReader::load_string("base: &b {x: 1}\none: *b\ntwo: *b\n", "ok.yaml"));
  const std::string empty = testing::TempDir() + "/empty.yaml";
  write_file_atomic(empty, "  \n");
  EXPECT_THROW(YamlReader::load_file(empty), InputError);
  EXPECT_THROW(YamlReader::load_file("/dev/zero"), InputError);
  // A bad block list is named on one line.
  YamlReader y = YamlReader::load_string("fruits:\n  - 1\n  - .nan\n", "w.yaml");
  try {
    y.fail("fruits", "must be finite");
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[1, .nan]"), std::string::npos) << e.what();
  }
}

// Named choices: the table's names parse, an absent key gives the fallback, anything else
// fails naming the file, key, value and the valid names.
enum class Fruit { kPepper, kTomato };
constexpr EnumName<Fruit> kFruitNames[] = {{Fruit::kPepper, "pepper"}, {Fruit::kTomato, "tomato"}};

TEST(YamlReader, ChoicesFromANameTable) {
  YamlReader y = YamlReader::load_string("a: tomato\nb: apple\n", "t.yaml");
  EXPECT_EQ(y.get_choice("a", Fruit::kPepper, kFruitNames), Fruit::kTomato);
  EXPECT_EQ(y.get_choice("missing", Fruit::kTomato, kFruitNames), Fruit::kTomato);
  try {
    y.get_choice("b", Fruit::kPepper, kFruitNames);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.yaml: key 'b': value 'apple' must be one of: pepper, tomato"),
              std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(y.finish());  // every key read
  EXPECT_STREQ(enum_name(kFruitNames, Fruit::kTomato), "tomato");
  EXPECT_EQ(enum_from_name(kFruitNames, "pepper", "--fruit", "fruit"), Fruit::kPepper);
  try {
    enum_from_name(kFruitNames, "kiwi", "--fruit", "fruit");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--fruit: unknown fruit 'kiwi' (valid: pepper, tomato)");
  }
}

TEST(YamlReader, RepeatedKeysAreErrorsNamingBothLines) {
  auto message = [](const std::string& text) {
    try {
      YamlReader::load_string(text, "w.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("seed: 1\nname: a\nseed: 2\n"), "w.yaml: duplicate key 'seed' at lines 1 and 3");
  EXPECT_EQ(message("rows:\n  rows: 2\n  plants_per_row: 3\n  rows: 1\n"),
            "w.yaml: duplicate key 'rows' at lines 2 and 4");
  EXPECT_EQ(message("a: [{x: 1, x: 2}]\n"), "w.yaml: duplicate key 'x' at lines 1 and 1");
  EXPECT_EQ(message("a: {x: 1}\nb: {x: 2}\n"), "no error");  // same key in two mappings is fine
}

TEST(YamlReader, AFolderIsNotAnEmptyFile) {
  try {
    YamlReader::load_file(testing::TempDir());
    FAIL() << "a folder loaded as a YAML file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_file(testing::TempDir()), InputError);
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
  EXPECT_EQ(file.aisle_clearance_m, defaults.aisle_clearance_m);
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
