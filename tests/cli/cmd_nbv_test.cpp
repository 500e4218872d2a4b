// `canopy nbv` on a saved map gives the views of the in-process planner (motion/view_reach.h),
// and each view's joints put the camera where the view says.

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include "canopy/common/read_file.h"
#include "canopy/common/value_text.h"
#include "canopy/common/process.h"
#include "canopy/mapping/map_io.h"
#include "canopy/nbv/planners/ours/ours_params.h"
#include "canopy/settings/settings.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/mission/mission.h"
#include "canopy/motion/view_reach.h"
#include "canopy/perception/semantic_extractor.h"
#include "canopy/sim/renderer.h"
#include "canopy/world/world_spec.h"

namespace fs = std::filesystem;
using namespace canopy;

namespace {

struct SavedMap {
  fs::path dir;
  std::unique_ptr<mapping::SemanticOcTree> map;
  SavedMap() {
    char tmpl[] = "/tmp/canopy_nbv_XXXXXX";
    dir = ::mkdtemp(tmpl);
    const world::World world = world::generate_world(world::WorldSpec::load(find_data_file("worlds/small.yaml")));
    sim::Simulator sim(world, default_robot_config());
    sim::Renderer renderer(sim, world.spec.camera);
    const settings::MappingSettings cfg;
    map = std::make_unique<mapping::SemanticOcTree>(cfg.map, world.spec.classes);
    mapping::ScanInserter inserter(*map);
    perception::SemanticExtractor extractor(cfg.extractor, world.spec.classes);
    for (const Pose& T : evaluation::aisle_views(world, 4)) inserter.insert(extractor.extract(renderer.render_free_camera(T)));
    mapping::save_map(*map, (dir / "map.csm").string());
  }
  ~SavedMap() { fs::remove_all(dir); }
};

}  // namespace

TEST(NbvCli, SavedMapGivesTheInProcessViews) {
  const SavedMap saved;
  const BasePose base{-0.3, 0.0, 0.0};
  const std::string out = (saved.dir / "views.json").string();
  const ProcessStatus st = run_process({CANOPY_CLI, "nbv", "--map", (saved.dir / "map.csm").string(), "--base",
                                        "-0.3,0,0", "--method", "ours", "--gain", "osamcep", "--k", "2", "--out", out});
  ASSERT_TRUE(st.ok()) << st.describe();
  const nlohmann::json j = nlohmann::json::parse(read_file(out));

  // In process, on the map in memory (not the file), with the shipped settings.
  const RobotConfig robot = default_robot_config();
  const motion::RobotModel model = motion::RobotModel::load(robot);
  settings::Settings settings = settings::Settings::load(find_data_file(settings::default_settings_path()), robot);
  settings.nbv.planner<nbv::OursParams>().top_k = 2;
  nbv::ViewPlannerSettings ps;
  ps.params = settings.nbv;
  const auto planner = nbv::make_view_planner(ps);
  motion::NextViewsRequest req;
  req.base = base;
  req.q = robot.home;
  const Vec3 arm = motion::RobotModel::T_world_base(base) * model.T_base_arm().translation();
  req.region = mission::stop_region(settings.mission.loop, arm.x(), arm.y());
  req.budget = settings.mission.loop.views_per_stop;
  const motion::NextViews nv = motion::plan_next_views(*saved.map, *planner, model, settings.motion, req);

  ASSERT_GE(nv.ordered.size(), 3u);  // a real batch: several clusters in reach
  ASSERT_EQ(j.at("views").size(), nv.ordered.size() + nv.unreachable.size());
  EXPECT_EQ(j.at("clusters").get<std::size_t>(), nv.batch.clusters);
  EXPECT_EQ(j.at("k").get<int>(), 2);
  for (std::size_t i = 0; i < nv.ordered.size(); ++i) {
    const nlohmann::json& v = j.at("views").at(i);
    const nbv::PlannedView& w = nv.ordered[i];
    EXPECT_EQ(v.at("tour_index").get<std::size_t>(), i);
    EXPECT_EQ(v.at("cluster").get<int>(), w.cluster);
    EXPECT_EQ(v.at("gain").get<double>(), w.gain);
    const Pose T = pose_from_json(v.at("T_world_camera"));
    EXPECT_LT((T.translation() - w.T_world_camera.translation()).norm(), 1e-12);
    EXPECT_LT((T.linear() - w.T_world_camera.linear()).norm(), 1e-12);
    ASSERT_TRUE(w.has_q);
    const ArmConfig q = v.at("joints").get<ArmConfig>();
    EXPECT_EQ(q, w.q);
    // The joints put the camera at the view (forward kinematics), within the joint limits.
    const Pose fk = model.camera_pose(base, q);
    EXPECT_LT((fk.translation() - T.translation()).norm(), 1e-6);
    EXPECT_LT(Eigen::AngleAxisd(fk.linear().transpose() * T.linear()).angle(), 1e-6);
    EXPECT_TRUE(model.within_limits(q));
  }
  // The tour is the tour solver's order of these views from the arm's home configuration.
  std::vector<ArmConfig> qs;
  std::vector<Vec3> cams;
  for (const nbv::PlannedView& w : nv.ordered) {
    qs.push_back(w.q);
    cams.push_back(w.T_world_camera.translation());
  }
  std::vector<int> identity(qs.size());
  for (std::size_t i = 0; i < identity.size(); ++i) identity[i] = static_cast<int>(i);
  EXPECT_EQ(motion::order_views(settings.motion.tour, robot.home, model.camera_pose(base, robot.home).translation(), qs,
                                cams),
            identity);
}
