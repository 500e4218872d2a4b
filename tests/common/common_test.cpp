#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "canopy/common/camera.h"
#include "canopy/common/classes.h"
#include "canopy/common/error.h"
#include "canopy/common/io.h"
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

TEST(Io, FormatNumberFollowsItsPrintfFormat) {
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(1.0 / 3.0), "0.333333333");
  EXPECT_EQ(std::stod(format_number(1.0 / 3.0, "%.17g")), 1.0 / 3.0);
  EXPECT_EQ(format_number(2.5, "%.3f"), "2.500");
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
    StagedDir d(out, "test");
    write_file_atomic(d.path("x.txt"), "x");
  }  // no commit: nothing left
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));
  {
    StagedDir d(out, "test");
    write_file_atomic(d.path("x.txt"), "x");
    d.commit();
  }
  EXPECT_TRUE(fs::exists(out + "/x.txt"));
  // A second run may replace canopy's own output...
  {
    StagedDir again(out, "test");
    write_file_atomic(again.path("y.txt"), "y");
    again.commit();
  }
  EXPECT_TRUE(fs::exists(out + "/y.txt"));
  EXPECT_FALSE(fs::exists(out + "/x.txt"));
  // ...but never a folder canopy did not write.
  const std::string foreign = testing::TempDir() + "/foreign_folder";
  fs::create_directories(foreign);
  write_file_atomic(foreign + "/precious.txt", "keep me");
  EXPECT_THROW(StagedDir(foreign, "test"), InputError);
  EXPECT_TRUE(fs::exists(foreign + "/precious.txt"));
}

TEST(Io, StagedDirResumeAddsToCanopyFoldersOnly) {
  namespace fs = std::filesystem;
  const std::string out = testing::TempDir() + "/staged_resume";
  fs::remove_all(out);
  fs::remove_all(out + ".partial");
  using Mode = StagedDir::Mode;
  {  // a fresh resume run that fails leaves nothing behind
    StagedDir d(out, "test", Mode::kResume);
    write_file_atomic(d.path("a.txt"), "a");
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));
  {
    StagedDir d(out, "test", Mode::kResume);
    EXPECT_EQ(d.working_dir(), out + ".partial");
    EXPECT_FALSE(d.resuming());
    write_file_atomic(d.path("a.txt"), "a");
    d.commit();
  }
  {  // resuming writes into the folder itself and keeps what is there, even on failure
    StagedDir d(out, "test", Mode::kResume);
    EXPECT_EQ(d.working_dir(), out);
    EXPECT_TRUE(d.resuming());
    write_file_atomic(d.make_subdir("jobs/x") + "/b.txt", "b");
  }
  EXPECT_EQ(read_file(out + "/a.txt"), "a");
  EXPECT_EQ(read_file(out + "/jobs/x/b.txt"), "b");
  // An interrupted run's .partial is picked up and published by commit().
  fs::remove_all(out);
  fs::create_directories(out + ".partial");
  write_file_atomic(out + ".partial/" + kOutputMarker, "x");
  write_file_atomic(out + ".partial/c.txt", "c");
  {
    StagedDir d(out, "test", Mode::kResume);
    EXPECT_EQ(d.working_dir(), out + ".partial");
    d.commit();
  }
  EXPECT_EQ(read_file(out + "/c.txt"), "c");
  EXPECT_FALSE(fs::exists(out + ".partial"));
  // A folder canopy did not write is refused in both modes, and stays as it was.
  const std::string foreign = testing::TempDir() + "/foreign_resume";
  fs::remove_all(foreign);
  fs::create_directories(foreign);
  write_file_atomic(foreign + "/metrics.json", "mine");
  EXPECT_THROW(StagedDir(foreign, "test", Mode::kResume), InputError);
  EXPECT_THROW(StagedDir(foreign, "test", Mode::kReplace), InputError);
  EXPECT_EQ(read_file(foreign + "/metrics.json"), "mine");
  EXPECT_EQ(fs::directory_iterator(foreign)->path().filename(), "metrics.json");
  EXPECT_FALSE(fs::exists(foreign + ".partial"));
  // An empty folder is fine (and becomes canopy's).
  const std::string empty = testing::TempDir() + "/empty_resume";
  fs::remove_all(empty);
  fs::create_directories(empty);
  {
    StagedDir d(empty, "test", Mode::kResume);
    EXPECT_EQ(d.working_dir(), empty);
  }
  EXPECT_TRUE(fs::exists(empty + "/" + kOutputMarker));
  // A file is not a folder.
  write_file_atomic(testing::TempDir() + "/a_file", "f");
  EXPECT_THROW(StagedDir(testing::TempDir() + "/a_file", "test"), InputError);
}

// Each folder's marker names its kind; output of another kind never replaces or joins it
// (an experiment is never replaced by a report), and two commands never write one folder.
TEST(Io, StagedDirKeepsKindsApartAndOneWriterAtATime) {
  namespace fs = std::filesystem;
  const std::string exp = testing::TempDir() + "/kind_experiment";
  fs::remove_all(exp);
  fs::create_directories(exp + "/trials/t1");
  write_output_marker(exp, "experiment");
  write_file_atomic(exp + "/experiment.json", "{}");
  EXPECT_EQ(output_kind(exp), "experiment");
  try {
    StagedDir d(exp, "report");
    FAIL() << "a report replaced an experiment";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("holds the output of `canopy experiment`"), std::string::npos) << e.what();
  }
  EXPECT_THROW(StagedDir(exp, "mission", StagedDir::Mode::kResume), InputError);
  EXPECT_TRUE(fs::exists(exp + "/experiment.json"));
  EXPECT_TRUE(fs::exists(exp + "/trials/t1"));
  EXPECT_NO_THROW(StagedDir::check_writable(exp, "experiment"));
  // An older marker without a kind may be replaced by any kind (as before).
  const std::string old = testing::TempDir() + "/kind_legacy";
  fs::remove_all(old);
  fs::create_directories(old);
  write_file_atomic(old + "/" + kOutputMarker, "written by canopy; a later run may replace this folder\n");
  EXPECT_EQ(output_kind(old), "any");
  EXPECT_NO_THROW(StagedDir::check_writable(old, "map"));
  EXPECT_EQ(output_kind(testing::TempDir()), "");
  // One writer: a second StagedDir on the same folder is refused while the first lives.
  const std::string out = testing::TempDir() + "/busy_out";
  fs::remove_all(out);
  {
    StagedDir first(out, "mission");
    write_file_atomic(first.path("views.csv"), "a");
    try {
      StagedDir second(out, "mission");
      FAIL() << "two writers";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("is busy"), std::string::npos) << e.what();
    }
    EXPECT_EQ(read_file(first.path("views.csv")), "a");  // the first one's files are untouched
    first.commit();
  }
  EXPECT_FALSE(fs::exists(out + ".lock"));
  EXPECT_NO_THROW(StagedDir(out, "mission"));  // free again
  // keep(): an interrupted run's folder stays for --resume.
  const std::string kept = testing::TempDir() + "/kept_out";
  fs::remove_all(kept);
  fs::remove_all(kept + ".partial");
  {
    StagedDir d(kept, "ablate");
    write_file_atomic(d.path("job.json"), "{}");
    d.keep();
  }
  EXPECT_TRUE(fs::exists(kept + ".partial/job.json"));
}

// Inputs that never end or claim absurd sizes are refused before anything is allocated.
TEST(Io, ReadFileAndPngRefuseDevicesAndAbsurdSizes) {
  EXPECT_THROW(read_file("/dev/zero"), InputError);
  const std::string big = testing::TempDir() + "/big.txt";
  write_file_atomic(big, std::string(2000, 'x'));
  EXPECT_THROW(read_file(big, 1000), InputError);
  EXPECT_EQ(read_file(big).size(), 2000u);
  // A PNG whose header claims 100000 x 100000 16-bit pixels (signature, IHDR, a token IDAT, IEND).
  const unsigned char png[] = {0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
                               0x44, 0x52, 0x00, 0x01, 0x86, 0xa0, 0x00, 0x01, 0x86, 0xa0, 0x10, 0x00, 0x00, 0x00,
                               0x00, 0xdd, 0xa9, 0x88, 0x57, 0x00, 0x00, 0x00, 0x0b, 0x49, 0x44, 0x41, 0x54, 0x78,
                               0x9c, 0x63, 0x60, 0x80, 0x00, 0x00, 0x00, 0x08, 0x00, 0x01, 0xb7, 0x58, 0x73, 0x95,
                               0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  const std::string path = testing::TempDir() + "/huge_header.png";
  write_file_atomic(path, std::string(reinterpret_cast<const char*>(png), sizeof png));
  try {
    read_png_gray16(path);
    FAIL() << "a 100000 x 100000 header was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("100000 x 100000"), std::string::npos) << e.what();
  }
}

TEST(Io, WholeNumbersAndShardsDoNotWrapAround) {
  EXPECT_EQ(parse_uint64("18446744073709551615", "--seed"), 18446744073709551615ull);
  EXPECT_EQ(parse_uint64("0", "--seed"), 0u);
  for (const char* bad : {"-1", "99999999999999999999", "18446744073709551616", "1e3", " 1", "", "0x10", "+5"})
    EXPECT_THROW(parse_uint64(bad, "--seed"), InputError) << bad;
  EXPECT_THROW(parse_uint64("11", "x", 10), InputError);
  EXPECT_THROW(parse_numbers("0x10,0,0", 3, "--base"), InputError);
  EXPECT_THROW(parse_numbers("inf,0,0", 3, "--base"), InputError);
  EXPECT_EQ(parse_numbers("-1.5e2, 2 ,3", 3, "--base")[0], -150.0);
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

TEST(Io, FailedRenameReportsTheRealError) {
  namespace fs = std::filesystem;
  // Writing a file over a non-empty folder fails in rename(): the message must carry that
  // error, not "Success".
  const std::string target = testing::TempDir() + "/rename_target";
  fs::remove_all(target);
  fs::create_directories(target + "/inside");
  try {
    write_file_atomic(target, "x");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find("Success"), std::string::npos) << msg;
    EXPECT_NE(msg.find(std::error_code(EISDIR, std::generic_category()).message()), std::string::npos) << msg;
  }
  EXPECT_TRUE(fs::is_directory(target + "/inside"));
  // The temporary file was removed.
  for (const auto& e : fs::directory_iterator(testing::TempDir()))
    EXPECT_EQ(e.path().filename().string().find("rename_target.tmp"), std::string::npos) << e.path();
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
