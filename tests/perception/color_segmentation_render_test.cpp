// Colour segmentation against the renderer's true labels on default-world images (OSMesa,
// headless), and the floor: white ground film is not fruit, a brown floor is.

#include <gtest/gtest.h>

#include "canopy/robot/robot_config.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/mapping/frame_mapping.h"
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

namespace {

// Maps aisle views of `world` with colour labels (no noise) and returns the share of the
// floor's pixels colour segmentation calls fruit and the map's fruit voxel precision.
struct FloorFigures {
  double floor_fruit_share = 0.0;
  std::size_t floor_pixels = 0;
  evaluation::FruitVoxelPrecision precision;
};

FloorFigures floor_figures(const world::World& world) {
  sim::Simulator sim(world, default_robot_config());
  sim::Renderer renderer(sim, world.spec.camera);
  const int fruit = world.spec.classes.index_of("fruit");
  perception::ExtractorParams ep;
  ep.source = perception::LabelSource::kColor;
  ep.p_gt = 1.0;
  perception::SemanticExtractor extractor(ep, world.spec.classes);
  mapping::SemanticOcTree map(mapping::SemanticMapParams{}, world.spec.classes);
  mapping::ScanInserter inserter(map);
  FloorFigures out;
  std::size_t floor_fruit = 0;
  // From the aisle, looking down at the foot of each row as a wrist camera does at low fruit,
  // and horizontally at the plants.
  std::vector<Pose> views = evaluation::aisle_views(world, 1, 0.45, 0.6);
  for (const auto& plant : world.plants) {
    const double side = plant.base_position.y() > 0.0 ? 1.0 : -1.0;
    views.push_back(look_at(Vec3(plant.base_position.x(), 0.0, 0.9), Vec3(plant.base_position.x() + 0.2, 0.4 * side, 0.0)));
  }
  for (const Pose& T : views) {
    const LabelledFrame f = renderer.render(T, /*show_robot=*/false);
    const Image<std::uint8_t> seg = perception::segment_by_color(f.rgb, perception::ColorSegmentationParams{}, world.spec.classes);
    for (std::size_t i = 0; i < seg.data.size(); ++i)
      if (f.class_id.data[i] == 0 && f.depth_m.data[i] > 0.f && f.instance.data[i] == kNoInstance) {
        // Background pixels with depth, robot hidden: the floor, the only background geometry.
        ++out.floor_pixels;
        floor_fruit += seg.data[i] == fruit;
      }
    mapping::map_frame(f, extractor, inserter);
  }
  out.floor_fruit_share = out.floor_pixels ? double(floor_fruit) / double(out.floor_pixels) : 0.0;
  evaluation::MetricsParams mp;
  mp.rule = evaluation::EvaluationRule::kPaper;  // every voxel whose most likely class is fruit
  out.precision = evaluation::evaluate_map(map, world.truth, mp).voxel_precision;
  return out;
}

}  // namespace

// The default floor (white ground film, concrete path) is not fruit to colour segmentation;
// a floor of fruit colour is, and the map's fruit voxel precision shows it.
TEST(ColorVsRender, TheDefaultFloorIsNotFruitAndAFruitColouredFloorLowersPrecision) {
  world::WorldSpec spec = world::WorldSpec::load(find_data_file("worlds/small.yaml"));
  const FloorFigures white = floor_figures(world::generate_world(spec));
  spec.ground.film_r = 0.42;  // the old brown checker's darker colour: hue ~15, inside the red/orange band
  spec.ground.film_g = 0.36;
  spec.ground.film_b = 0.30;
  const FloorFigures brown = floor_figures(world::generate_world(spec));
  std::printf("floor pixels labelled fruit: white film %.4f of %zu, brown %.4f of %zu; paper-rule fruit voxel "
              "precision: white %.3f (%zu false), brown %.3f (%zu false)\n",
              white.floor_fruit_share, white.floor_pixels, brown.floor_fruit_share, brown.floor_pixels,
              white.precision.precision, white.precision.false_voxels, brown.precision.precision,
              brown.precision.false_voxels);
  ASSERT_GT(white.floor_pixels, 1000u);
  EXPECT_LE(white.floor_fruit_share, 0.001);
  EXPECT_GE(brown.floor_fruit_share, 0.8);  // measured 0.90 (shaded floor falls out of the band)
  EXPECT_GT(white.precision.precision, 0.6);
  EXPECT_LT(brown.precision.precision, 0.5 * white.precision.precision);
}
