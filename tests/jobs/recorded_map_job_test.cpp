// The recorded-map job against analytic frames: a camera 0.5 m from a wall of leaf maps the
// same wall wherever on Earth its frame puts it (a recording 600 m or 5,000 km from its
// frame's origin is anchored, and frames.json says where), and frames that put no point in
// the map are an error that writes nothing.

#include <gtest/gtest.h>

#include <filesystem>

#include "canopy/common/error.h"
#include "canopy/common/read_file.h"
#include "canopy/jobs/recorded_map_job.h"
#include "canopy/mapping/map_io.h"

namespace canopy::jobs {
namespace {

namespace fs = std::filesystem;

// `count` frames of a camera at `at` looking along +z at a wall `depth_m` away, all leaf.
RecordedSequence wall(const Vec3& at, float depth_m, std::size_t count) {
  RecordedSequence seq;
  seq.source = "analytic frames";
  seq.size = count;
  seq.name = [](std::size_t i) { return "frame" + std::to_string(i); };
  seq.read = [at, depth_m](std::size_t i, LabelledFrame* f, std::string*) {
    f->intrinsics.width_px = 64;
    f->intrinsics.height_px = 48;
    f->intrinsics.fx_px = f->intrinsics.fy_px = 60.0;
    f->intrinsics.cx_px = 32.0;
    f->intrinsics.cy_px = 24.0;
    f->T_world_camera = Pose::Identity();
    f->T_world_camera.translation() = at + Vec3(0.01 * static_cast<double>(i), 0.0, 0.0);
    f->depth_m = Image<float>(64, 48, depth_m);
    f->class_id = Image<std::uint8_t>(64, 48, 1);
    return true;
  };
  return seq;
}

RecordedMapParams params(const std::string& out) {
  RecordedMapParams p;
  p.settings = settings::Settings::defaults(default_robot_config());
  p.settings.mapping.extractor.source = perception::LabelSource::kTruth;
  p.settings.mapping.extractor.p_gt = 1.0;
  p.out = out;
  return p;
}

std::vector<double> map_origin(const std::string& dir) {
  return nlohmann::json::parse(read_file(dir + "/frames.json")).at("map_origin_m").get<std::vector<double>>();
}

TEST(RecordedMapJob, AFarRecordingMapsAsOneNearItsFramesOrigin) {
  const std::string dir = testing::TempDir() + "/recorded_far";
  fs::remove_all(dir);
  const RecordedMapResult near = map_recorded(wall(Vec3(0.2, -0.3, 0.6), 0.5f, 3), params(dir + "/near"));
  ASSERT_GT(near.occupied_voxels, 100u);
  EXPECT_EQ(map_origin(dir + "/near"), (std::vector<double>{0.0, 0.0, 0.0}));  // near the origin: not moved
  for (const Vec3& far : {Vec3(600.2, -0.3, 0.6), Vec3(-250.2, 399.7, 0.6), Vec3(4.5e6, 5.2e6, 30.6)}) {
    const std::string out = dir + "/far";
    const RecordedMapResult r = map_recorded(wall(far, 0.5f, 3), params(out));
    // The same wall: the same number of voxels, give or take the grid's phase under the shift.
    EXPECT_NEAR(static_cast<double>(r.occupied_voxels), static_cast<double>(near.occupied_voxels),
                0.1 * static_cast<double>(near.occupied_voxels))
        << far.transpose();
    const std::vector<double> o = map_origin(out);
    ASSERT_EQ(o.size(), 3u);
    EXPECT_LT((Vec3(o[0], o[1], o[2]) - far).norm(), 0.02) << far.transpose();  // at the first camera
    // Every occupied voxel lies where the wall is, in the map's (anchored) frame.
    const mapping::SemanticOcTree map = mapping::load_map(out + "/map.csm");
    std::size_t occupied = 0;
    map.for_each_voxel_if([](const mapping::SemanticState& v) { return v.occupancy_logodds() > 0.f; },
                          [&](const octomap::OcTreeKey& key, const mapping::SemanticState&) {
                            ++occupied;
                            EXPECT_NEAR(map.center_of(key).z() + o[2], far.z() + 0.5, 0.03) << far.transpose();
                          });
    EXPECT_EQ(occupied, r.occupied_voxels);
  }
}

TEST(RecordedMapJob, FramesThatPutNoPointInTheMapAreAnError) {
  const std::string out = testing::TempDir() + "/recorded_empty";
  fs::remove_all(out);
  try {
    map_recorded(wall(Vec3::Zero(), 0.0f, 2), params(out));  // depth 0: every pixel invalid
    FAIL() << "an empty map was published";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2 frames mapped, but none put a point in the map"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));
  EXPECT_FALSE(fs::exists(out + ".lock"));
}

// run.yaml is the caller's record with the mask noise the frames were mapped with added last;
// a record that states it (Python's map-bag does) is written as given.
TEST(RecordedMapJob, RunRecordGetsTheMaskNoiseUnlessItStatesIt) {
  const std::string dir = testing::TempDir() + "/recorded_run_record";
  fs::remove_all(dir);
  RecordedSequence seq = wall(Vec3(0.0, 0.0, 0.6), 0.5f, 2);
  seq.run["command"] = "map";
  seq.run["frames"] = "somewhere";
  RecordedMapParams p = params(dir + "/added");
  p.settings.mapping.extractor.p_gt = 0.7;
  map_recorded(seq, p);
  YAML::Node run = YAML::LoadFile(dir + "/added/run.yaml");
  std::vector<std::string> keys;
  for (const auto& kv : run) keys.push_back(kv.first.as<std::string>());
  EXPECT_EQ(keys, (std::vector<std::string>{"command", "frames", "p_gt"}));
  EXPECT_EQ(run["p_gt"].as<double>(), 0.7);
  EXPECT_FALSE(seq.run["p_gt"]) << "the caller's record is not changed";

  seq.run["p_gt"] = 0.5;  // stated by the caller: kept
  map_recorded(seq, params(dir + "/stated"));
  run = YAML::LoadFile(dir + "/stated/run.yaml");
  EXPECT_EQ(run["p_gt"].as<double>(), 0.5);
}

}  // namespace
}  // namespace canopy::jobs
