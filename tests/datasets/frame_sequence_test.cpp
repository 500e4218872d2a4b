// Recorded sequences: TUM timestamp association, file parsing and the errors bad files give.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "canopy/common/error.h"
#include "canopy/common/png_io.h"
#include "canopy/common/params.h"
#include "canopy/datasets/frame_io.h"
#include "canopy/datasets/frame_sequence.h"
#include "canopy/world/world_spec.h"

namespace fs = std::filesystem;
using namespace canopy;
using namespace canopy::datasets;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    char tmpl[] = "/tmp/canopy_frames_XXXXXX";
    path = ::mkdtemp(tmpl);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

void write_text(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
}

// The message of the InputError `f` throws ("" when it throws none).
template <typename F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A TUM folder of `n` 8x6 frames: RGB at t = i / 10 s, depth jittered by `jitter[i]`, a
// depth image missing for `missing_depth`, poses at the depth times except `missing_pose`.
void write_tum(const TempDir& d, int n, const std::vector<double>& jitter, int missing_depth, int missing_pose) {
  write_text(d / "camera.yaml",
             "width_px: 8\nheight_px: 6\nfx_px: 10\nfy_px: 10\ncx_px: 4\ncy_px: 3\nmin_range_m: 0.1\n"
             "max_range_m: 2.0\n");
  std::string rgb = "# timestamp filename\n", depth = "# depth\n", gt = "# timestamp tx ty tz qx qy qz qw\n";
  for (int i = 0; i < n; ++i) {
    char name[64], line[256];
    const double t = 0.1 * i, td = t + jitter[static_cast<std::size_t>(i)];
    std::snprintf(name, sizeof name, "%.6f.png", t);
    Image<Rgb8> c(8, 6, Rgb8{200, 10, 10});
    fs::create_directories(d.path / "rgb");
    fs::create_directories(d.path / "depth");
    write_png(d / ("rgb/" + std::string(name)), c);
    std::snprintf(line, sizeof line, "%.6f rgb/%s\n", t, name);
    rgb += line;
    if (i != missing_depth) {
      Image<std::uint16_t> z(8, 6, static_cast<std::uint16_t>(5000 + 500 * i));  // 1.0 m + 0.1 m * i
      write_png_gray16(d / ("depth/" + std::string(name)), z);
      std::snprintf(line, sizeof line, "%.6f depth/%s\n", td, name);
      depth += line;
    }
    if (i != missing_pose) {
      std::snprintf(line, sizeof line, "%.6f %d 0 0 0 0 0 1\n", td, i);
      gt += line;
    }
  }
  write_text(d / "rgb.txt", rgb);
  write_text(d / "depth.txt", depth);
  write_text(d / "groundtruth.txt", gt);
}

}  // namespace

TEST(FrameSequence, AssociationIsOneToOneNearestWithinTolerance) {
  // Depth jittered by up to 12 ms around 30 Hz RGB; depth 3 missing; one stray depth far off.
  const std::vector<double> rgb = {0.0, 0.033, 0.066, 0.100, 0.133};
  const std::vector<double> depth = {0.140, 0.004, 0.045, -0.012, 0.078, 0.5};  // unsorted on purpose
  const auto pairs = associate_timestamps(rgb, depth, 0.02);
  // rgb 0 -> 0.004 (not -0.012), 1 -> 0.045, 2 -> 0.078, 3 -> none (its depth is missing:
  // the nearest are 22 and 40 ms away), 4 -> 0.140.
  const std::vector<std::pair<std::size_t, std::size_t>> want = {{0, 1}, {1, 2}, {2, 4}, {4, 0}};
  EXPECT_EQ(pairs, want);
  // A reference: every pair is within the tolerance and no index is used twice.
  std::vector<int> used(depth.size(), 0);
  for (const auto& [i, j] : pairs) {
    EXPECT_LE(std::abs(rgb[i] - depth[j]), 0.02);
    EXPECT_EQ(used[j]++, 0);
  }
  EXPECT_TRUE(associate_timestamps(rgb, depth, 1e-4).empty());
  // Two RGB images near one depth image: the closer one gets it, the other none.
  const std::vector<std::pair<std::size_t, std::size_t>> one = {{1, 0}};
  EXPECT_EQ(associate_timestamps({0.0, 0.010}, {0.006}, 0.02), one);
}

TEST(FrameSequence, NearestTimestamp) {
  const std::vector<double> t = {0.0, 0.01, 0.02, 0.05};
  EXPECT_EQ(nearest_timestamp(t, 0.011, 0.005), 1);
  EXPECT_EQ(nearest_timestamp(t, 0.016, 0.005), 2);
  EXPECT_EQ(nearest_timestamp(t, 0.035, 0.005), -1);
  EXPECT_EQ(nearest_timestamp(t, -0.004, 0.005), 0);
  EXPECT_EQ(nearest_timestamp({}, 0.0, 1.0), -1);
}

TEST(FrameSequence, TumWithJitterMissingDepthAndMissingPose) {
  TempDir d;
  write_tum(d, 6, {0.004, -0.006, 0.009, 0.0, -0.003, 0.007}, /*missing_depth=*/2, /*missing_pose=*/4);
  const FrameSequence s = FrameSequence::open(d.path.string());
  EXPECT_EQ(s.layout(), FrameLayout::kTum);
  ASSERT_EQ(s.size(), 4u);  // frames 0, 1, 3, 5
  ASSERT_EQ(s.skipped().size(), 2u);
  EXPECT_EQ(s.skipped()[0].name, "0.200000.png");
  EXPECT_EQ(s.skipped()[0].reason, "no depth image within 0.02 s");
  EXPECT_EQ(s.skipped()[1].name, "0.400000.png");
  EXPECT_EQ(s.skipped()[1].reason, "no ground-truth pose within 0.02 s");
  const int kept[] = {0, 1, 3, 5};
  for (std::size_t k = 0; k < s.size(); ++k) {
    LabelledFrame f;
    std::string why;
    ASSERT_TRUE(s.read(k, &f, &why)) << why;
    const int i = kept[k];
    // The right depth image (1 m + 0.1 m i at 5000 per metre) and the right pose (x = i).
    EXPECT_FLOAT_EQ(f.depth_m.at(3, 2), static_cast<float>((5000 + 500 * i) / 5000.0));
    EXPECT_DOUBLE_EQ(f.T_world_camera.translation().x(), i);
    EXPECT_EQ(f.intrinsics.fx_px, 10.0);
  }
}

TEST(FrameSequence, FramesWithoutValidDepthAreSkipped) {
  TempDir d;
  write_tum(d, 2, {0.0, 0.0}, -1, -1);
  write_png_gray16(d / "depth/0.100000.png", Image<std::uint16_t>(8, 6, 60000));  // 12 m: out of range
  const FrameSequence s = FrameSequence::open(d.path.string());
  LabelledFrame f;
  std::string why;
  EXPECT_TRUE(s.read(0, &f, &why));
  EXPECT_FALSE(s.read(1, &f, &why));
  EXPECT_EQ(why, "no depth pixel within the valid range");
}

TEST(FrameSequence, BadFilesNameFileAndLine) {
  TempDir d;
  write_tum(d, 3, {0.0, 0.0, 0.0}, -1, -1);
  EXPECT_EQ(input_error([&] { FrameSequence::open(d / "missing"); }), d / "missing" + ": no such folder (--frames)");
  // A malformed line, named with its number.
  write_text(d / "groundtruth.txt", "# header\n0.0 0 0 0 0 0 0 1\n0.1 0 0 zero 0 0 0 1\n");
  EXPECT_EQ(input_error([&] { FrameSequence::open(d.path.string()); }),
            d / "groundtruth.txt" + ":3: 'zero' is not a finite number");
  write_text(d / "groundtruth.txt", "0.0 0 0 0 0 0 1\n");
  EXPECT_NE(input_error([&] { FrameSequence::open(d.path.string()); }).find("groundtruth.txt:1: expected 'timestamp tx ty tz qx qy qz qw', found 7 fields"),
            std::string::npos);
  // A non-unit quaternion.
  write_text(d / "groundtruth.txt", "0.0 0 0 0 0 0 0 1\n0.1 0 0 0 0.5 0 0 1\n");
  EXPECT_EQ(input_error([&] { FrameSequence::open(d.path.string()); }),
            d / "groundtruth.txt" + ":2: quaternion has norm 1.118034, must be unit length");
  write_text(d / "groundtruth.txt", "0.0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 1\n0.2 0 0 0 0 0 0 1\n");
  write_text(d / "rgb.txt", "0.0 rgb/0.000000.png extra\n");
  EXPECT_EQ(input_error([&] { FrameSequence::open(d.path.string()); }),
            d / "rgb.txt" + ":1: expected 'timestamp file', found 3 fields");
  write_text(d / "rgb.txt", "0.000000 rgb/0.000000.png\n0.100000 rgb/0.100000.png\n");
  // Depth in the wrong format: 8-bit, or the wrong size.
  write_png(d / "depth/0.000000.png", Image<Rgb8>(8, 6));
  write_png_gray16(d / "depth/0.100000.png", Image<std::uint16_t>(6, 8, 5000));
  const FrameSequence s = FrameSequence::open(d.path.string());
  LabelledFrame f;
  std::string why;
  EXPECT_EQ(input_error([&] { s.read(0, &f, &why); }), d / "depth/0.000000.png" + ": expected a 16-bit grayscale PNG");
  EXPECT_EQ(input_error([&] { s.read(1, &f, &why); }),
            d / "depth/0.100000.png" + ": image is 6x8 but the camera is 8x6");
  // Camera YAML: validated, unknown keys rejected.
  write_text(d / "camera.yaml", "width_px: 8\nheight_px: 6\nfx_px: -1\nfy_px: 10\ncx_px: 4\ncy_px: 3\n");
  EXPECT_EQ(input_error([&] { FrameSequence::open(d.path.string()); }), d / "camera.yaml" + ": key 'fx_px': value '-1' must be > 0");
  write_text(d / "camera.yaml", "width_px: 8\nheight_px: 6\nfx_px: 1\nfy_px: 10\ncx_px: 4\ncy_px: 3\ndepth_scale: 5000\n");
  EXPECT_NE(input_error([&] { FrameSequence::open(d.path.string()); }).find("unknown key 'depth_scale'"), std::string::npos);
  write_text(d / "camera.yaml", "width_px: 8\nheight_px: 6\nfx_px: 1\nfy_px: 10\ncx_px: 4\ncy_px: 3\ndepth_scale_per_m: 0\n");
  EXPECT_NE(input_error([&] { FrameSequence::open(d.path.string()); }).find("depth_scale_per_m"), std::string::npos);
  // A folder with neither layout.
  fs::create_directories(d.path / "empty");
  EXPECT_NE(input_error([&] { FrameSequence::open(d / "empty"); }).find("no frames"), std::string::npos);
}

TEST(FrameSequence, LabelImagesDecodeByTableAndNameAnUnknownColour) {
  TempDir d;
  write_text(d / "table.yaml",
             "classes: [background, leaf, fruit]\ntarget: fruit\n"
             "colors: {background: [0, 0, 0], leaf: [0, 200, 0], fruit: [250, 0, 0]}\n");
  const ClassColorTable t = ClassColorTable::load(d / "table.yaml");
  Image<Rgb8> img(3, 2, Rgb8{0, 0, 0});
  img.at(1, 0) = {0, 200, 0};
  img.at(2, 1) = {250, 0, 0};
  const Image<std::uint8_t> ids = t.decode(img, "x.png");
  EXPECT_EQ(ids.data, (std::vector<std::uint8_t>{0, 1, 0, 0, 0, 2}));
  img.at(0, 1) = {1, 2, 3};
  EXPECT_EQ(input_error([&] { t.decode(img, "labels/f.png"); }),
            "labels/f.png: colour (1, 2, 3) at pixel (0, 1) is not in the class-colour table");
  write_text(d / "twice.yaml", "classes: [background, fruit]\ncolors: {background: [0, 0, 0], fruit: [0, 0, 0]}\n");
  EXPECT_NE(input_error([&] { ClassColorTable::load(d / "twice.yaml"); }).find("repeats the colour of class 'background'"),
            std::string::npos);
  write_text(d / "missing.yaml", "classes: [background, fruit]\ncolors: {background: [0, 0, 0]}\n");
  EXPECT_NE(input_error([&] { ClassColorTable::load(d / "missing.yaml"); }).find("missing key 'colors.fruit'"),
            std::string::npos);
  // The default table is the classes' drawing colours (what labels.png holds).
  const ClassColorTable def = ClassColorTable::from_classes(SemanticClasses{});
  EXPECT_EQ(def.colors[2], SemanticClasses{}.color(2));
}

namespace {

// A canopy frame folder whose frame.json holds `intrinsics` (a JSON object) and the range.
void write_frame_json(const std::string& folder, const std::string& intrinsics, const std::string& range) {
  write_text(folder + "/frame.json",
             "{\"intrinsics\": " + intrinsics + ", \"valid_range_m\": " + range +
                 ", \"depth_noise_k\": 0.0, \"T_world_camera\": {\"position\": [0, 0, 0], \"quaternion_wxyz\": [1, 0, "
                 "0, 0]}, \"classes\": [\"background\", \"leaf\", \"fruit\"]}\n");
}

// The pinhole keys as a flow mapping (YAML and JSON alike), with `key` set to `value`.
std::string pinhole(const std::string& key, const std::string& value) {
  const std::pair<std::string, std::string> keys[] = {{"width_px", "400"}, {"height_px", "400"}, {"fx_px", "381.36"},
                                                      {"fy_px", "381.36"}, {"cx_px", "200"},     {"cy_px", "200"}};
  std::string s;
  for (const auto& [k, v] : keys) s += (s.empty() ? "" : ", ") + ("\"" + k + "\": " + (k == key ? value : v));
  return "{" + s + "}";
}

// The default intrinsics with `key` set to `value` (as the Python Intrinsics builds them).
CameraIntrinsics with(const std::string& key, const std::string& value) {
  CameraIntrinsics K;
  const double v = std::stod(value);
  if (key == "width_px") K.width_px = static_cast<int>(v);
  if (key == "height_px") K.height_px = static_cast<int>(v);
  if (key == "fx_px") K.fx_px = v;
  if (key == "fy_px") K.fy_px = v;
  if (key == "cx_px") K.cx_px = v;
  if (key == "cy_px") K.cy_px = v;
  if (key == "min_range_m") K.min_range_m = v;
  if (key == "max_range_m") K.max_range_m = v;
  return K;
}

}  // namespace

// One set of camera limits (CameraIntrinsics::visit): the same bad value gets the same problem
// from a world file's camera, a TUM sequence's camera.yaml, a frame folder's frame.json and
// the Python Intrinsics (validate_recorded_intrinsics).
TEST(CameraLimits, SameFromEveryEntryPoint) {
  TempDir d;
  write_tum(d, 1, {0.0}, -1, -1);
  const std::tuple<std::string, std::string, std::string> cases[] = {
      {"width_px", "4097", "must be in [1, 4096]"},     {"height_px", "0", "must be in [1, 4096]"},
      {"fx_px", "-1", "must be > 0"},                   {"fy_px", "0", "must be > 0"},
      {"cx_px", "401", "must lie in the image (0 to width_px)"},
      {"cy_px", "-1", "must lie in the image (0 to height_px)"},
  };
  for (const auto& [key, value, problem] : cases) {
    const std::string yaml = pinhole(key, value);
    write_text(d / "world.yaml", "camera: " + yaml + "\n");
    EXPECT_EQ(input_error([&] { world::WorldSpec::load(d / "world.yaml"); }),
              d / "world.yaml" + ": key 'camera." + key + "': value '" + value + "' " + problem);
    write_text(d / "camera.yaml", yaml + "\n");
    EXPECT_EQ(input_error([&] { FrameSequence::open(d.path.string()); }),
              d / "camera.yaml" + ": key '" + key + "': value '" + value + "' " + problem);
    write_frame_json(d / "frames/f0", yaml, "[0.07, 1.0]");
    EXPECT_EQ(input_error([&] { FrameSequence::open(d / "frames"); }),
              d / "frames/f0/frame.json" + ": key 'intrinsics." + key + "': value '" + value + "' " + problem);
    const std::string python = input_error([&] { validate_recorded_intrinsics(with(key, value), "Intrinsics"); });
    EXPECT_NE(python.find(key), std::string::npos) << python;
    EXPECT_NE(python.find(problem), std::string::npos) << python;
  }
  // The depth range: frame.json holds it as valid_range_m, checked against the same limits.
  const std::tuple<std::string, std::string, std::string, std::string> ranges[] = {
      {"min_range_m", "0", "[0, 1.0]", "must be > 0"},
      {"max_range_m", "0.05", "[0.07, 0.05]", "must be > min_range_m"},
  };
  for (const auto& [key, value, range, problem] : ranges) {
    write_text(d / "world.yaml", "camera: {" + key + ": " + value + "}\n");
    EXPECT_EQ(input_error([&] { world::WorldSpec::load(d / "world.yaml"); }),
              d / "world.yaml" + ": key 'camera." + key + "': value '" + value + "' " + problem);
    write_text(d / "camera.yaml", "width_px: 400\nheight_px: 400\nfx_px: 381.36\nfy_px: 381.36\ncx_px: 200\ncy_px: 200\n" +
                                      key + ": " + value + "\n");
    EXPECT_EQ(input_error([&] { FrameSequence::open(d.path.string()); }),
              d / "camera.yaml" + ": key '" + key + "': value '" + value + "' " + problem);
    write_frame_json(d / "frames/f0", pinhole("", ""), range);
    const std::string frame_error = input_error([&] { FrameSequence::open(d / "frames"); });
    EXPECT_NE(frame_error.find(d / "frames/f0/frame.json"), std::string::npos) << frame_error;
    EXPECT_NE(frame_error.find(key), std::string::npos) << frame_error;
    EXPECT_NE(frame_error.find(problem), std::string::npos) << frame_error;
    const std::string python = input_error([&] { validate_recorded_intrinsics(with(key, value), "Intrinsics"); });
    EXPECT_NE(python.find(key), std::string::npos) << python;
    EXPECT_NE(python.find(problem), std::string::npos) << python;
  }
}

// frame.json's intrinsics as write_frame puts them, read back by the frame folder reader.
TEST(CameraLimits, FrameJsonIntrinsicsReadBack) {
  TempDir d;
  CameraIntrinsics K;
  K.width_px = 64;
  K.height_px = 48;
  K.fx_px = 50.5;
  K.fy_px = 51.0;
  K.cx_px = 31.5;
  K.cy_px = 24.25;
  K.min_range_m = 0.1;
  K.max_range_m = 2.5;
  K.depth_noise_k = 0.01;
  nlohmann::json j;
  put_frame_intrinsics(&j, K);
  EXPECT_EQ(j["intrinsics"].size(), 6u);  // the layout frame folders have always had
  EXPECT_EQ(j["valid_range_m"], nlohmann::json({0.1, 2.5}));
  EXPECT_EQ(j["depth_noise_k"], 0.01);
  j["T_world_camera"] = {{"position", {0, 0, 0}}, {"quaternion_wxyz", {1, 0, 0, 0}}};
  j["classes"] = {"background", "leaf", "fruit"};
  write_text(d / "f0/frame.json", j.dump());
  const FrameSequence s = FrameSequence::open(d / "f0");
  ASSERT_EQ(s.size(), 1u);
  write_png_gray16(d / "f0/depth.png", Image<std::uint16_t>(64, 48, 1000));
  write_png(d / "f0/rgb.png", Image<Rgb8>(64, 48));
  LabelledFrame f;
  std::string why;
  ASSERT_TRUE(s.read(0, &f, &why)) << why;
  K.depth_noise_k = 0.0;  // what the renderer added is not a property of the recorded frame
  EXPECT_TRUE(same_params(f.intrinsics, K)) << yaml_text(params_to_yaml(f.intrinsics));
}
