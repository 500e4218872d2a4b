// Frames rendered by the simulator, written as canopy frame folders and as a TUM RGB-D
// sequence and read back, build the same map as the frames in memory (identical leaves).

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "canopy/datasets/frame_io.h"
#include "canopy/datasets/frame_sequence.h"
#include "canopy/common/png_io.h"
#include "canopy/datasets/sequence_mapping.h"
#include "canopy/mapping/map_io.h"
#include "canopy/settings/settings.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/sim/renderer.h"
#include "canopy/world/world_spec.h"

namespace fs = std::filesystem;
using namespace canopy;
using namespace canopy::datasets;

namespace {

constexpr int kViews = 4;
constexpr double kDepthJitterS = 0.004;  // depth stamped 4 ms after RGB, poses at the depth time

struct Recorded {
  world::World world;
  std::vector<LabelledFrame> frames;  ///< Depth quantised to millimetres, as files hold it.
  fs::path dir;

  Recorded() : world(world::generate_world(world::WorldSpec::load(find_data_file("worlds/small.yaml")))) {
    char tmpl[] = "/tmp/canopy_recorded_XXXXXX";
    dir = ::mkdtemp(tmpl);
    sim::Simulator sim(world, default_robot_config());
    sim::Renderer renderer(sim, world.spec.camera);
    const std::vector<Pose> views = evaluation::ring_views(world);
    for (int i = 0; i < kViews; ++i) {
      LabelledFrame f = renderer.render_free_camera(views[static_cast<std::size_t>(i) * 2]);
      // Files hold millimetres and a unit quaternion: the in-memory frame gets the same.
      for (float& z : f.depth_m.data)
        z = z > 0.f ? static_cast<float>(std::min(65535.0, std::round(1000.0 * z)) / 1000.0) : 0.f;
      f.T_world_camera = make_pose(f.T_world_camera.translation(), Quat(f.T_world_camera.linear()));
      frames.push_back(std::move(f));
    }
    write_canopy();
    write_tum();
  }
  ~Recorded() { fs::remove_all(dir); }

  void write_canopy() const {
    for (int i = 0; i < kViews; ++i) {
      const fs::path d = dir / "canopy" / ("f" + std::to_string(i));
      fs::create_directories(d);
      write_frame(d.string() + "/", frames[static_cast<std::size_t>(i)], world.spec.classes);
    }
  }

  void write_tum() const {
    const fs::path d = dir / "tum";
    for (const char* sub : {"rgb", "depth", "labels"}) fs::create_directories(d / sub);
    const CameraIntrinsics& K = frames[0].intrinsics;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "width_px: %d\nheight_px: %d\nfx_px: %.17g\nfy_px: %.17g\ncx_px: %.17g\ncy_px: %.17g\n"
                  "min_range_m: %.17g\nmax_range_m: %.17g\ndepth_scale_per_m: 5000\n",
                  K.width_px, K.height_px, K.fx_px, K.fy_px, K.cx_px, K.cy_px, K.min_range_m, K.max_range_m);
    std::ofstream(d / "camera.yaml") << buf;
    std::ofstream rgb(d / "rgb.txt"), depth(d / "depth.txt"), gt(d / "groundtruth.txt");
    // A pose between frames, as a motion-capture stream has, which association must not pick.
    gt << "# timestamp tx ty tz qx qy qz qw\n0.05 0 0 0 0 0 0 1\n";
    for (int i = 0; i < kViews; ++i) {
      const LabelledFrame& f = frames[static_cast<std::size_t>(i)];
      const double t = 1.0 + 0.1 * i;
      std::snprintf(buf, sizeof buf, "%.6f.png", t);
      const std::string name = buf;
      write_png(d / "rgb" / name, f.rgb);
      Image<std::uint16_t> z(f.depth_m.width, f.depth_m.height, 0);
      for (std::size_t k = 0; k < z.data.size(); ++k)
        z.data[k] = static_cast<std::uint16_t>(std::lround(5000.0 * f.depth_m.data[k]));
      write_png_gray16((d / "depth" / name).string(), z);
      Image<Rgb8> labels(f.class_id.width, f.class_id.height);
      for (std::size_t k = 0; k < labels.data.size(); ++k) labels.data[k] = world.spec.classes.color(f.class_id.data[k]);
      write_png((d / "labels" / name).string(), labels);
      std::snprintf(buf, sizeof buf, "%.6f rgb/%s\n", t, name.c_str());
      rgb << buf;
      std::snprintf(buf, sizeof buf, "%.6f depth/%s\n", t + kDepthJitterS, name.c_str());
      depth << buf;
      const Vec3 p = f.T_world_camera.translation();
      const Quat q(f.T_world_camera.linear());
      std::snprintf(buf, sizeof buf, "%.6f %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", t + kDepthJitterS, p.x(),
                    p.y(), p.z(), q.x(), q.y(), q.z(), q.w());
      gt << buf;
      gt << 0.05 + t << " 5 5 5 0 0 0 1\n";
    }
  }
};

const Recorded& recorded() {
  static const Recorded r;
  return r;
}

std::string map_in_memory(const settings::MappingSettings& cfg) {
  const Recorded& r = recorded();
  mapping::SemanticOcTree map(cfg.map, r.world.spec.classes);
  mapping::ScanInserter inserter(map);
  perception::SemanticExtractor extractor(cfg.extractor, r.world.spec.classes);
  for (const LabelledFrame& f : r.frames) mapping::map_frame(f, extractor, inserter);
  EXPECT_GT(map.counts().occupied, 500u);
  return mapping::serialize_map(map);
}

std::string map_from_files(const std::string& folder, const settings::MappingSettings& cfg, bool label_images,
                           FrameLayout layout) {
  FrameReaderOptions o;
  o.label_images = label_images;
  const FrameSequence frames = FrameSequence::open((recorded().dir / folder).string(), o);
  EXPECT_EQ(frames.layout(), layout);
  EXPECT_EQ(frames.size(), std::size_t(kViews));
  EXPECT_EQ(frames.classes().names, recorded().world.spec.classes.names);
  mapping::SemanticOcTree map(cfg.map, frames.classes());
  mapping::ScanInserter inserter(map);
  perception::SemanticExtractor extractor(cfg.extractor, frames.classes());
  const datasets::SequenceMapResult r = datasets::map_sequence(frames, extractor, inserter);
  EXPECT_EQ(r.mapped, std::size_t(kViews));
  EXPECT_TRUE(r.skipped.empty());
  return mapping::serialize_map(map);
}

}  // namespace

TEST(RecordedFrames, ColorSegmentedFilesMapLikeMemory) {
  settings::MappingSettings cfg;  // colour segmentation with the default P_gt noise and seed
  ASSERT_EQ(cfg.extractor.source, perception::LabelSource::kColor);
  const std::string memory = map_in_memory(cfg);
  EXPECT_TRUE(memory == map_from_files("canopy", cfg, false, FrameLayout::kCanopy));
  EXPECT_TRUE(memory == map_from_files("tum", cfg, false, FrameLayout::kTum));
}

TEST(RecordedFrames, LabelImagesMapLikeTrueLabels) {
  settings::MappingSettings cfg;
  cfg.extractor.source = perception::LabelSource::kTruth;
  cfg.extractor.p_gt = 1.0;  // file labels carry no instance ids, so no mask noise to compare
  const std::string memory = map_in_memory(cfg);
  EXPECT_TRUE(memory == map_from_files("canopy", cfg, true, FrameLayout::kCanopy));
  EXPECT_TRUE(memory == map_from_files("tum", cfg, true, FrameLayout::kTum));
  // And they differ from colour segmentation's map (the comparison can fail).
  EXPECT_FALSE(memory == map_in_memory(settings::MappingSettings{}));
}
