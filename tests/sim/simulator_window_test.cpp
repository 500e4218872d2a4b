// A long row's window built ahead (issue 49): Simulator::prepare_plants_near compiles on
// another thread the model show_plants_near builds itself; it must be that model bit for bit.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "canopy/common/camera.h"
#include "canopy/sim/renderer.h"
#include "plant_window_scene.h"

namespace canopy::sim {
namespace {

// The compiled model as MuJoCo saves it (MJB): every array of the model, names included.
std::vector<unsigned char> mjb_bytes(const mjModel* m) {
  std::vector<unsigned char> bytes(static_cast<std::size_t>(mj_sizeModel(m)));
  mj_saveModel(m, nullptr, bytes.data(), static_cast<int>(bytes.size()));
  return bytes;
}


// Each geom's label as the simulator gave it before issue 49's rebuilds were timed: by
// mj_name2id of every labelled name.
std::vector<GeomLabel> labels_by_name2id_per_label(const Simulator& sim) {
  const mjModel* m = sim.render_model();
  std::vector<GeomLabel> out(static_cast<std::size_t>(m->ngeom));
  for (const auto& [name, label] : sim.scene().labels) {
    const int id = mj_name2id(m, mjOBJ_GEOM, name.c_str());
    if (id >= 0) out[static_cast<std::size_t>(id)] = label;
  }
  return out;
}

void expect_labels_as_by_name2id(const Simulator& sim) {
  const std::vector<GeomLabel> reference = labels_by_name2id_per_label(sim);
  int labelled = 0;
  for (int g = 0; g < sim.render_model()->ngeom; ++g) {
    const GeomLabel& a = sim.geom_label(g);
    const GeomLabel& b = reference[static_cast<std::size_t>(g)];
    EXPECT_EQ(a.class_id, b.class_id) << g;
    EXPECT_EQ(a.instance_id, b.instance_id) << g;
    EXPECT_EQ(a.robot, b.robot) << g;
    labelled += a.instance_id != kNoInstance;
  }
  EXPECT_GT(labelled, 20);  // the plant parts (instances) of a 6 m window
}

TEST(SimulatorWindow, APreparedWindowIsTheModelBuiltOnArrivalBitForBit) {
  const world::World w = world::generate_world(test::long_row_spec());
  const RobotConfig cfg = default_robot_config();
  Simulator ahead(w, cfg, test::two_section_window()), on_arrival(w, cfg, test::two_section_window());
  Renderer ahead_renderer(ahead, w.spec.camera), arrival_renderer(on_arrival, w.spec.camera);
  EXPECT_EQ(mjb_bytes(ahead.render_model()), mjb_bytes(on_arrival.render_model()));
  expect_labels_as_by_name2id(ahead);

  EXPECT_TRUE(ahead.holds_plants_near(0.0, 0.0));
  EXPECT_FALSE(ahead.holds_plants_near(12.0, 12.0));
  EXPECT_FALSE(ahead.prepare_plants_near(0.0, 0.0));  // the window held covers it
  EXPECT_EQ(ahead.prepared_plant_window_x(), std::make_pair(0.0, 0.0));
  ASSERT_TRUE(ahead.prepare_plants_near(12.0, 12.0));
  EXPECT_FALSE(ahead.prepare_plants_near(12.0, 12.0));  // under way
  const std::pair<double, double> prepared_x = ahead.prepared_plant_window_x();
  const int generation = ahead.render_generation();
  // The robot works meanwhile: the held model is the old window's until the move.
  ArmConfig q = cfg.home;
  q[0] += 0.3;
  for (Simulator* sim : {&ahead, &on_arrival}) {
    sim->set_robot_state(BasePose{12.0, 0.0, 0.0}, q);
    sim->step(20);
  }
  EXPECT_EQ(ahead.render_generation(), generation);
  ASSERT_TRUE(ahead.show_plants_near(12.0, 12.0));
  ASSERT_TRUE(on_arrival.show_plants_near(12.0, 12.0));
  EXPECT_EQ(ahead.plant_window(), on_arrival.plant_window());
  EXPECT_EQ(ahead.plant_window_x(), prepared_x);
  EXPECT_EQ(ahead.prepared_plant_window_x(), std::make_pair(0.0, 0.0));  // taken
  EXPECT_EQ(mjb_bytes(ahead.render_model()), mjb_bytes(on_arrival.render_model()));
  expect_labels_as_by_name2id(ahead);

  // Depth, labels and colour from fixed poses and the wrist, bit for bit.
  const LabelledFrame a = ahead_renderer.render_wrist_camera(), b = arrival_renderer.render_wrist_camera();
  EXPECT_EQ(a.rgb.data, b.rgb.data);
  EXPECT_EQ(a.depth_m.data, b.depth_m.data);
  EXPECT_EQ(a.class_id.data, b.class_id.data);
  EXPECT_EQ(a.instance.data, b.instance.data);
  int plant_pixels = 0;
  for (int i = 0; i < 6; ++i) {
    const Pose T = look_at(Vec3(11.4 + 0.25 * i, 0.25, 0.4 + 0.1 * i), Vec3(11.6 + 0.2 * i, 0.75, 0.7));
    const LabelledFrame f = ahead_renderer.render_free_camera(T), g = arrival_renderer.render_free_camera(T);
    EXPECT_EQ(f.rgb.data, g.rgb.data) << i;
    EXPECT_EQ(f.depth_m.data, g.depth_m.data) << i;
    EXPECT_EQ(f.class_id.data, g.class_id.data) << i;
    EXPECT_EQ(f.instance.data, g.instance.data) << i;
    plant_pixels += static_cast<int>(std::count(f.class_id.data.begin(), f.class_id.data.end(), w.spec.class_of("leaf")));
  }
  EXPECT_GT(plant_pixels, 1000);
}

TEST(SimulatorWindow, AWindowPreparedButNotTakenIsDroppedForTheOneAskedFor) {
  const world::World w = world::generate_world(test::long_row_spec());
  const RobotConfig cfg = default_robot_config();
  Simulator sim(w, cfg, test::two_section_window()), fresh(w, cfg, test::two_section_window());
  ASSERT_TRUE(sim.prepare_plants_near(6.0, 6.0));
  ASSERT_TRUE(sim.prepare_plants_near(9.0, 9.0));  // another window: the first is dropped
  ASSERT_TRUE(sim.show_plants_near(12.0, 12.0));   // neither
  ASSERT_TRUE(fresh.show_plants_near(12.0, 12.0));
  EXPECT_EQ(sim.plant_window(), fresh.plant_window());
  EXPECT_EQ(mjb_bytes(sim.render_model()), mjb_bytes(fresh.render_model()));
  expect_labels_as_by_name2id(sim);
  ASSERT_TRUE(sim.prepare_plants_near(0.0, 0.0));  // left when the simulator goes: it waits for it
}

}  // namespace
}  // namespace canopy::sim
