// The MuJoCo robot agrees with the URDF description, its arm settles at commanded joint
// positions and its base reaches commanded planar poses.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/motion/base_follower.h"
#include "canopy/robot/robot_description.h"
#include "canopy/sim/renderer.h"
#include "plant_window_scene.h"

namespace canopy::sim {
namespace {

world::WorldSpec tiny_world() {
  world::WorldSpec s;
  s.rows.rows = 1;
  s.rows.plants_per_row = 1;
  return s;
}

TEST(RobotSim, CameraPoseAgreesWithTheUrdfChain) {
  const RobotConfig cfg = default_robot_config();
  const robot::RobotDescription d = robot::RobotDescription::load_urdf(cfg.urdf_path);
  Simulator sim(world::generate_world(tiny_world()), cfg);
  Rng rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const BasePose base{rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-M_PI, M_PI)};
    ArmConfig q{};
    for (auto& v : q) v = rng.uniform(-M_PI, M_PI);
    sim.set_robot_state(base, q);
    robot::JointPositions jp{{cfg.base_joints[0], base.x_m}, {cfg.base_joints[1], base.y_m}, {cfg.base_joints[2], base.yaw_rad}};
    for (int i = 0; i < kArmDof; ++i) jp[cfg.arm_joints[static_cast<size_t>(i)]] = q[static_cast<size_t>(i)];
    const Pose expected = d.link_pose(cfg.camera_frame, jp);
    const Pose actual = sim.camera_pose();
    EXPECT_LT((actual.translation() - expected.translation()).norm(), 1e-6);
    EXPECT_LT((actual.linear() - expected.linear()).norm(), 1e-6);
    const Pose tool = sim.frame_pose(cfg.tool_frame);
    EXPECT_LT((tool.translation() - d.link_pose(cfg.tool_frame, jp).translation()).norm(), 1e-6);
  }
}

TEST(RobotSim, ArmSettlesAtCommandedConfiguration) {
  const RobotConfig cfg = default_robot_config();
  Simulator sim(world::generate_world(tiny_world()), cfg);
  const ArmConfig targets[] = {{-1.2, -1.0, 1.8, 0.9, -1.2, 0.4}, {-2.9, -0.3, 2.0, 1.5, -0.5, -1.0}, cfg.home};
  for (const ArmConfig& target : targets) {
    sim.set_arm_targets(target);
    sim.step(static_cast<int>(4.0 / sim.timestep()));
    const ArmConfig q = sim.arm_positions();
    for (int i = 0; i < kArmDof; ++i) EXPECT_NEAR(q[static_cast<size_t>(i)], target[static_cast<size_t>(i)], 1e-3) << "joint " << i;
  }
}

// A move repeated from a restored snapshot (the mission does so when it started a move before
// the last scan was in the map) passes through the same states as the move made once.
TEST(RobotSim, SteppingOnFromARestoredSnapshotIsBitIdentical) {
  const RobotConfig cfg = default_robot_config();
  ASSERT_TRUE(cfg.gravity_compensation);
  Simulator sim(world::generate_world(tiny_world()), cfg);
  sim.set_arm_targets({-1.2, -1.0, 1.8, 0.9, -1.2, 0.4});
  sim.set_base_velocity(0.2, 0.3);
  sim.step(300);  // mid-move: the arm and the base are moving
  const SimState mid = sim.snapshot();
  auto move = [&sim] {
    std::vector<std::vector<double>> states;
    for (int k = 0; k < 40; ++k) {
      sim.set_arm_targets({-2.0 + 0.01 * k, -0.5, 1.5, 1.0, -1.0, 0.2});
      sim.step(5);
      const SimState s = sim.snapshot();
      std::vector<double> v = s.qpos;
      v.insert(v.end(), s.qvel.begin(), s.qvel.end());
      v.push_back(s.time);
      states.push_back(v);
    }
    return states;
  };
  const auto once = move();
  sim.restore(mid);
  const auto again = move();
  ASSERT_EQ(once.size(), again.size());
  for (std::size_t k = 0; k < once.size(); ++k)
    for (std::size_t i = 0; i < once[k].size(); ++i)
      ASSERT_EQ(once[k][i], again[k][i]) << "state " << k << ", value " << i;  // exact: bit for bit
}

TEST(RobotSim, BaseReachesCommandedPlanarPoses) {
  const RobotConfig cfg = default_robot_config();
  Simulator sim(world::generate_world(tiny_world()), cfg);
  const BasePose goals[] = {{0.2, 0.0, 0.0}, {0.9, 0.15, 0.5}, {0.4, -0.1, -1.2}};
  const double dt = sim.timestep();
  for (const BasePose& goal : goals) {
    motion::BaseFollower follower(motion::BaseFollowerParams::from_robot(cfg), {goal});
    bool done = false;
    for (int k = 0; k < static_cast<int>(30.0 / dt) && !done; ++k) {
      const motion::BaseCommand cmd = follower.update(sim.base_pose(), dt);
      ASSERT_TRUE(cmd.fault.empty()) << cmd.fault;
      done = cmd.done;
      sim.set_base_velocity(cmd.v_m_s, cmd.omega_rad_s);
      sim.step();
    }
    EXPECT_TRUE(done);
    const BasePose p = sim.base_pose();
    EXPECT_NEAR(p.x_m, goal.x_m, 0.02);
    EXPECT_NEAR(p.y_m, goal.y_m, 0.02);
    EXPECT_NEAR(wrap_angle(p.yaw_rad - goal.yaw_rad), 0.0, M_PI / 180.0);
  }
}

TEST(RobotSim, WristCameraSeesThePlantFromHome) {
  world::WorldSpec spec = tiny_world();
  spec.robot_start = BasePose{-0.2, 0.0, 0.0};  // arm base (x + 0.2) in front of the plant at x = 0
  const world::World w = world::generate_world(spec);
  Simulator sim(w, default_robot_config());
  Renderer renderer(sim, spec.camera);
  const LabelledFrame f = renderer.render_wrist_camera();
  int leaf = 0, valid = 0;
  for (size_t i = 0; i < f.class_id.data.size(); ++i) {
    leaf += f.class_id.data[i] == spec.classes.index_of("leaf");
    valid += f.depth_m.data[i] > 0.f;
  }
  EXPECT_GT(leaf, 500);
  EXPECT_GT(valid, 500);
}

// The robot's link tree as a mission hands it to Python: every URDF link with a frame site,
// each under its nearest such ancestor, the camera frame among them, and each pose the link's
// frame pose now.
TEST(RobotSim, RobotLinksAreATreeOfFramedLinks) {
  const RobotConfig cfg = default_robot_config();
  const robot::RobotDescription d = robot::RobotDescription::load_urdf(cfg.urdf_path);
  Simulator sim(world::generate_world(tiny_world()), cfg);
  sim.set_robot_state(BasePose{0.3, -0.2, 0.5}, cfg.home);
  const RobotLinks links = sim.robot_links();
  ASSERT_FALSE(links.links.empty());
  ASSERT_EQ(links.parents.size(), links.links.size());
  ASSERT_EQ(links.poses.size(), links.links.size());
  bool camera = false;
  for (std::size_t i = 0; i < links.links.size(); ++i) {
    const std::string& name = links.links[i];
    camera |= name == cfg.camera_frame;
    EXPECT_NE(name, "world");
    // The parent is the root or a link listed before it, and an ancestor in the URDF.
    const auto earlier = std::find(links.links.begin(), links.links.begin() + static_cast<long>(i), links.parents[i]);
    EXPECT_TRUE(links.parents[i] == "world" || earlier != links.links.begin() + static_cast<long>(i)) << name;
    int at = -1;
    for (std::size_t k = 0; k < d.links().size(); ++k)
      if (d.links()[k].name == name) at = static_cast<int>(k);
    ASSERT_GE(at, 0) << name << " is not a URDF link";
    if (links.parents[i] != "world") {
      bool ancestor = false;
      for (int up = d.parent_link(at); up >= 0; up = d.parent_link(up)) ancestor |= d.links()[up].name == links.parents[i];
      EXPECT_TRUE(ancestor) << links.parents[i] << " is not above " << name;
    }
    EXPECT_TRUE(links.poses[i].isApprox(sim.frame_pose(name))) << name;
  }
  EXPECT_TRUE(camera) << "the camera frame " << cfg.camera_frame << " is not a framed link";
  // Without a robot: no links.
  SceneDescription empty;
  empty.mjcf = "<mujoco><worldbody/></mujoco>";
  EXPECT_TRUE(Simulator(empty).robot_links().links.empty());
}

// The scene's MJCF text (every plant vertex written out as numbers) is not held once compiled
// (issue 49: a long row's was kept for the whole mission); its labels still name the rendered
// model's geoms, and the text make_scene_mjcf gives again compiles to the same plants.
TEST(RobotSim, TheSceneTextIsNotKeptOnceCompiled) {
  const RobotConfig cfg = default_robot_config();
  const world::World w = world::generate_world(tiny_world());
  Simulator sim(w, cfg);
  EXPECT_TRUE(sim.scene().mjcf.empty());
  const SceneDescription again = make_scene_mjcf(w, robot::RobotDescription::load_urdf(cfg.urdf_path), cfg);
  EXPECT_GT(again.mjcf.size(), 10000u);
  ASSERT_EQ(sim.scene().labels.size(), again.labels.size());
  int plant_geoms = 0;
  for (const auto& [name, label] : again.labels) {
    const int id = mj_name2id(sim.render_model(), mjOBJ_GEOM, name.c_str());
    ASSERT_GE(id, 0) << name;
    EXPECT_EQ(sim.geom_label(id).class_id, label.class_id) << name;
    plant_geoms += name.rfind("p0_", 0) == 0;
  }
  EXPECT_GT(plant_geoms, 10);
  SceneDescription bare;
  bare.mjcf = "<mujoco><worldbody/></mujoco>";
  EXPECT_TRUE(Simulator(bare).scene().mjcf.empty());
}

// The rendered model per section (issue 49): plant_window_scene.h's row and window.
// The base x of the plant each plant geom of the rendered model belongs to.
std::vector<double> rendered_plants_x(const Simulator& sim, const world::World& w) {
  std::map<std::string, double> x_of;
  for (const auto& plant : w.plants)
    for (const auto& part : plant.parts) x_of[part.name] = plant.base_position.x();
  std::vector<double> out;
  const mjModel* m = sim.render_model();
  for (int g = 0; g < m->ngeom; ++g) {
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    if (name && x_of.count(name)) out.push_back(x_of.at(name));
  }
  return out;
}

TEST(RobotSim, AWorldThatFitsInOneWindowIsBuiltWhole) {
  const world::World w = world::generate_world(world::WorldSpec{});  // the default: 2 rows of 4
  Simulator windowed(w, default_robot_config(), test::two_section_window());
  Simulator whole(w, default_robot_config());
  EXPECT_FALSE(windowed.plants_windowed());
  EXPECT_FALSE(windowed.show_plants_near(100.0, 100.0));
  EXPECT_EQ(windowed.render_generation(), 0);
  EXPECT_EQ(windowed.render_model()->ngeom, whole.render_model()->ngeom);
  EXPECT_EQ(windowed.render_model()->nmeshvert, whole.render_model()->nmeshvert);
  EXPECT_EQ(rendered_plants_x(windowed, w).size(), rendered_plants_x(whole, w).size());
  // A long row of fewer triangles than asked for a window is built whole too (the ablation's
  // world, 15 m; the default world's rows made 100 plants long).
  world::WorldSpec spec = test::long_row_spec();
  const world::World row = world::generate_world(spec);
  SceneOptions few = test::two_section_window();
  few.plant_window_min_triangles = static_cast<double>(row.triangle_count()) + 1.0;
  EXPECT_FALSE(Simulator(row, default_robot_config(), few).plants_windowed());
  few.plant_window_min_triangles = static_cast<double>(row.triangle_count());
  EXPECT_TRUE(Simulator(row, default_robot_config(), few).plants_windowed());
}

// A whole world of more triangles than one rendered model holds is refused with a message
// naming it (the compartment took minutes and gigabytes before failing); with a window, or only
// some plants asked for, it is built.
TEST(RobotSim, AWholeWorldTooLargeForOneModelIsRefusedNamingIt) {
  const world::World row = world::generate_world(test::long_row_spec());
  SceneOptions small;
  small.whole_max_triangles = static_cast<double>(row.triangle_count()) - 1.0;
  try {
    Simulator sim(row, default_robot_config(), small);
    ADD_FAILURE() << "built a whole world above the limit";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("world '" + row.spec.name + "': " + std::to_string(row.triangle_count()) + " plant triangles"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("canopy mission"), std::string::npos) << what;
  }
  SceneOptions windowed = test::two_section_window();
  windowed.plant_window_min_triangles = 0.0;
  windowed.whole_max_triangles = small.whole_max_triangles;
  EXPECT_TRUE(Simulator(row, default_robot_config(), windowed).plants_windowed());
  SceneOptions some = small;
  some.plants_from_x_m = 0.0;
  some.plants_to_x_m = 3.0;
  EXPECT_GT(Simulator(row, default_robot_config(), some).render_model()->ngeom, 0);
  small.whole_max_triangles = static_cast<double>(row.triangle_count());  // at the limit: built
  EXPECT_FALSE(Simulator(row, default_robot_config(), small).plants_windowed());
}

TEST(RobotSim, TheRenderedModelHoldsTheSectionsNearTheBaseAndFollowsIt) {
  const world::World w = world::generate_world(test::long_row_spec());
  Simulator sim(w, default_robot_config(), test::two_section_window());
  ASSERT_TRUE(sim.plants_windowed());
  EXPECT_EQ(sim.plant_sections(), 7);  // 19.5 m of plants
  // At the start (x = -0.8): the first two sections, the plants of [0, 6) m.
  EXPECT_EQ(sim.plant_window(), std::make_pair(0, 2));
  const auto within = [&](double lo, double hi) {
    const std::vector<double> xs = rendered_plants_x(sim, w);
    if (xs.empty()) return false;
    for (double x : xs)
      if (x < lo || x >= hi) return false;
    return true;
  };
  EXPECT_TRUE(within(0.0, 6.0));
  const int all_geoms = Simulator(w, default_robot_config()).render_model()->ngeom;
  EXPECT_LT(sim.render_model()->ngeom, all_geoms);
  EXPECT_FALSE(sim.show_plants_near(2.0, 3.0));  // held already
  const int built = sim.render_generation();
  // The robot moves on with its arm away from home; a base at 12 m needs [10.5, 13.5] m.
  ArmConfig q = default_robot_config().home;
  q[0] += 0.4;
  q[2] -= 0.3;
  sim.set_robot_state(BasePose{12.0, 0.1, 0.2}, q);
  EXPECT_TRUE(sim.show_plants_near(12.0, 12.0));
  EXPECT_EQ(sim.render_generation(), built + 1);
  EXPECT_EQ(sim.plant_window(), std::make_pair(3, 5));
  EXPECT_TRUE(within(9.0, 15.0));
  EXPECT_FALSE(sim.show_plants_near(12.5, 12.5));
  // The joint state carried over to the new rendered model.
  for (int i = 0; i < sim.model()->nq; ++i) EXPECT_EQ(sim.render_data()->qpos[i], sim.data()->qpos[i]) << i;
  // The last sections, and past the row's end the window stays on them.
  EXPECT_TRUE(sim.show_plants_near(30.0, 30.0));
  EXPECT_EQ(sim.plant_window(), std::make_pair(5, 7));
  EXPECT_FALSE(sim.show_plants_near(40.0, 40.0));
  // A range wider than a window gets every section it needs.
  EXPECT_TRUE(sim.show_plants_near(0.0, 12.0));
  EXPECT_EQ(sim.plant_window(), std::make_pair(0, 5));
  EXPECT_EQ(sim.render_generation(), built + 3);
  // The labels follow the model: every geom's label is its part's.
  std::map<std::string, int> instance_of;
  for (const auto& plant : w.plants)
    for (const auto& part : plant.parts) instance_of[part.name] = part.instance_id;
  int fruits = 0;
  for (int g = 0; g < sim.render_model()->ngeom; ++g) {
    const char* name = mj_id2name(sim.render_model(), mjOBJ_GEOM, g);
    if (!name || !instance_of.count(name)) continue;
    EXPECT_EQ(sim.geom_label(g).instance_id, instance_of.at(name)) << name;
    fruits += instance_of.at(name) != kNoInstance;
  }
  EXPECT_GT(fruits, 0);
}

}  // namespace
}  // namespace canopy::sim
