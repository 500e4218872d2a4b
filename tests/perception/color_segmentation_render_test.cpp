// Colour segmentation against the renderer's true labels on default-world images (OSMesa,
// headless).

#include <gtest/gtest.h>

#include "canopy/robot/robot_config.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/perception/color_segmentation.h"
#include "canopy/sim/renderer.h"
#include "canopy/world/world.h"

using namespace canopy;

TEST(ColorVsRender, AgreesWithTrueLabelsOnFruitAndLeafPixels) {
  const world::WorldSpec spec = world::WorldSpec::load(find_data_file("worlds/default.yaml"));
  const world::World world = world::generate_world(spec);
  sim::Simulator sim(world, default_robot_config());
  sim::Renderer renderer(sim, spec.camera);
  const int fruit = spec.classes.index_of("fruit"), leaf = spec.classes.index_of("leaf");
  std::size_t total = 0, agree = 0, fruit_total = 0, fruit_agree = 0;
  // Aisle views of both rows: every plant, as the robot sees them.
  for (const Pose& T : evaluation::aisle_views(world, 4)) {
    const LabelledFrame f = renderer.render_free_camera(T);
    const Image<std::uint8_t> seg = perception::segment_by_color(f.rgb, perception::ColorSegmentationParams{}, spec.classes);
    for (std::size_t i = 0; i < seg.data.size(); ++i) {
      const int truth = f.class_id.data[i];
      if (truth != fruit && truth != leaf) continue;
      ++total;
      agree += seg.data[i] == truth;
      if (truth == fruit) {
        ++fruit_total;
        fruit_agree += seg.data[i] == truth;
      }
    }
  }
  ASSERT_GT(total, 10000u);
  ASSERT_GT(fruit_total, 500u);
  const double share = double(agree) / double(total);
  RecordProperty("agreement", std::to_string(share));
  std::printf("colour vs truth: %.4f of %zu fruit and leaf pixels agree; fruit pixels %.4f of %zu\n", share, total,
              double(fruit_agree) / double(fruit_total), fruit_total);
  EXPECT_GE(share, 0.95);
}
