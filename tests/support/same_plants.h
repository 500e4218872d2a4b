#pragma once
// Bit-for-bit comparisons of generated plants and ground truth (issue 49: a plant generated
// alone, or again after its parts were dropped, must be the one the whole world's generation
// made).

#include <gtest/gtest.h>

#include <string>

#include "canopy/world/world.h"

namespace canopy::test {

inline void expect_same_plant(const world::Plant& a, const world::Plant& b) {
  const std::string at = "plant " + std::to_string(a.index);
  EXPECT_EQ(a.index, b.index) << at;
  EXPECT_EQ(a.base_position, b.base_position) << at;
  EXPECT_EQ(a.height_m, b.height_m) << at;
  EXPECT_EQ(a.import_dir, b.import_dir) << at;
  EXPECT_EQ(a.fruits_drawn, b.fruits_drawn) << at;
  EXPECT_EQ(a.fruits_placed, b.fruits_placed) << at;
  EXPECT_EQ(a.first_instance, b.first_instance) << at;
  EXPECT_EQ(a.triangles, b.triangles) << at;
  ASSERT_EQ(a.parts.size(), b.parts.size()) << at;
  for (std::size_t k = 0; k < a.parts.size(); ++k) {
    const world::PlantPart &p = a.parts[k], &q = b.parts[k];
    const std::string part = at + " part " + p.name;
    EXPECT_EQ(p.name, q.name) << part;
    EXPECT_EQ(p.kind, q.kind) << part;
    EXPECT_EQ(p.material, q.material) << part;
    EXPECT_EQ(p.class_id, q.class_id) << part;
    EXPECT_EQ(p.instance_id, q.instance_id) << part;
    EXPECT_EQ(p.fruit_color, q.fruit_color) << part;
    EXPECT_EQ(p.fruit_shape, q.fruit_shape) << part;
    EXPECT_EQ(p.fruit_target, q.fruit_target) << part;
    EXPECT_EQ(p.has_truth_points, q.has_truth_points) << part;
    EXPECT_EQ(p.truth_points, q.truth_points) << part;
    EXPECT_EQ(p.truth_area_m2, q.truth_area_m2) << part;
    for (int c = 0; c < 4; ++c) EXPECT_EQ(p.rgba[c], q.rgba[c]) << part;
    EXPECT_EQ(p.mesh.vertices, q.mesh.vertices) << part;  // exact, not near
    EXPECT_EQ(p.mesh.faces, q.mesh.faces) << part;
    EXPECT_EQ(p.texture, q.texture) << part;
    EXPECT_EQ(p.texture_file, q.texture_file) << part;
    ASSERT_EQ(p.uv.size(), q.uv.size()) << part;
    for (std::size_t f = 0; f < p.uv.size(); ++f)
      for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(p.uv[f][c], q.uv[f][c]) << part;
  }
}

inline void expect_same_truth(const world::GroundTruth& a, const world::GroundTruth& b) {
  EXPECT_EQ(a.point_spacing_m, b.point_spacing_m);
  ASSERT_EQ(a.fruits.size(), b.fruits.size());
  for (std::size_t i = 0; i < a.fruits.size(); ++i) {
    const world::FruitTruth &f = a.fruits[i], &g = b.fruits[i];
    EXPECT_EQ(f.instance_id, g.instance_id);
    EXPECT_EQ(f.plant_index, g.plant_index);
    EXPECT_EQ(f.color, g.color);
    EXPECT_EQ(f.shape, g.shape);
    EXPECT_EQ(f.target, g.target);
    EXPECT_EQ(f.center, g.center);
    EXPECT_EQ(f.bbox_min, g.bbox_min);
    EXPECT_EQ(f.bbox_max, g.bbox_max);
    EXPECT_EQ(f.surface_area_m2, g.surface_area_m2);
    EXPECT_EQ(f.volume_m3, g.volume_m3);
    EXPECT_EQ(f.surface_points, g.surface_points) << "fruit " << f.instance_id;
  }
}

}  // namespace canopy::test
