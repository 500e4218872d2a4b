// The reach job (jobs/reach_job.h), what canopy reach does: the views around the fruits in
// reach, tested for IK and collision, written as reach.json (settings as their C++ types) and
// reach.png (each view's dot coloured by its outcome); bad parameters refused before any work.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "canopy/common/error.h"
#include "canopy/common/png_io.h"
#include "canopy/common/read_file.h"
#include "canopy/jobs/reach_job.h"

namespace canopy::jobs {
namespace {

namespace fs = std::filesystem;

ReachJobParams small_reach(const std::string& out) {
  ReachJobParams p;
  p.world_file = "worlds/small.yaml";
  p.motion = motion::MotionConfig::defaults(default_robot_config());
  p.base = BasePose{-0.3, 0.0, 0.0};
  p.grid.sphere.azimuth_count = 6;
  p.grid.sphere.polar_count = 2;
  p.grid.plan = false;
  p.out = out;
  return p;
}

TEST(ReachJob, WritesTheFractionsAndTheMapOfEveryView) {
  const fs::path dir = fs::path(::testing::TempDir()) / "reach_job";
  fs::remove_all(dir);
  const ReachJobResult r = reach(small_reach(dir.string()));
  const motion::ReachReport& report = r.report;
  ASSERT_GT(report.targets, 0);
  ASSERT_EQ(report.samples.size(), static_cast<std::size_t>(report.targets) * 6 * 2);
  EXPECT_GT(report.count_ik(), 0);
  EXPECT_LE(report.count_collision_free(), report.count_ik());
  EXPECT_EQ(report.count_planned(), 0);  // no planning asked
  const nlohmann::json j = nlohmann::json::parse(read_file((dir / "reach.json").string()));
  EXPECT_EQ(j.at("world_file"), "worlds/small.yaml");
  EXPECT_EQ(j.at("grid").at("azimuth_count"), 6);  // an integer, as the struct holds it
  EXPECT_TRUE(j.at("grid").at("azimuth_count").is_number_integer());
  EXPECT_EQ(j.at("grid").at("plan"), false);
  EXPECT_TRUE(j.at("motion_config").at("planner").is_object());
  EXPECT_EQ(j.at("png").at("planned"), nlohmann::json({30, 160, 60}));
  const Image<Rgb8> png = read_png_rgb((dir / "reach.png").string());
  EXPECT_EQ(png.width, 2 * 520 + 4);
  EXPECT_EQ(png.height, 520);
  // The map the job drew is what reach_map draws of the same report.
  const motion::RobotModel model = motion::RobotModel::load(default_robot_config());
  nlohmann::json legend;
  const Image<Rgb8> again = reach_map(report, model, model.config().home, {}, &legend);
  EXPECT_EQ(legend, j.at("png"));
  EXPECT_EQ(again.width, png.width);
  fs::remove_all(dir);
}

// Each view is a dot of its outcome's colour where the top view puts its camera.
TEST(ReachJob, TheMapColoursEachViewByItsOutcome) {
  const motion::RobotModel model = motion::RobotModel::load(default_robot_config());
  motion::ReachReport report;
  report.base = BasePose{1.0, 2.0, 0.0};
  const Vec3 arm = (motion::RobotModel::T_world_base(report.base) * model.T_base_arm()).translation();
  const std::vector<Vec3> offsets = {{0.0, 1.0, 0.0}, {0.0, -1.0, 0.0}, {1.0, 1.0, 0.0}, {1.0, -1.0, 0.0}};
  for (int k = 0; k < 4; ++k) {
    motion::ReachSample s;
    s.T_world_camera.translation() = arm + offsets[static_cast<std::size_t>(k)];
    s.target = arm + Vec3(50, 50, 0);  // off the map
    s.ik = k >= 1;
    s.collision_free = k >= 2;
    s.planned = k >= 3;
    report.samples.push_back(s);
  }
  nlohmann::json legend;
  const Image<Rgb8> map = reach_map(report, model, model.config().home, {}, &legend);
  const char* keys[] = {"no_ik", "ik_but_in_collision", "collision_free_plan_failed", "planned"};
  for (int k = 0; k < 4; ++k) {
    const Vec3& d = offsets[static_cast<std::size_t>(k)];
    const int px = static_cast<int>(std::lround((d.x() + 1.3) / 2.6 * 519));
    const int py = static_cast<int>(std::lround((1.3 - d.y()) / 2.6 * 519));
    const Rgb8 c = map.at(px, py);
    EXPECT_EQ(nlohmann::json({c.r, c.g, c.b}), legend.at(keys[k])) << keys[k];
  }
}

TEST(ReachJob, BadParametersAreRefusedBeforeAnyWork) {
  const fs::path dir = fs::path(::testing::TempDir()) / "reach_job_bad";
  ReachJobParams p = small_reach(dir.string());
  p.voxel_m = 0.5;
  EXPECT_THROW(reach(p), InputError);
  p = small_reach(dir.string());
  p.grid.sphere.radius_m = -1.0;
  EXPECT_THROW(reach(p), InputError);
  p = small_reach(dir.string());
  p.joints = ArmConfig{9, 9, 9, 9, 9, 9};
  p.joints_where = "--joints";
  try {
    reach(p);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--joints: outside the joint limits");
  }
  EXPECT_FALSE(fs::exists(dir));  // nothing written
}

}  // namespace
}  // namespace canopy::jobs
