#pragma once
// A small analytic scene for nbv tests: fruit and leaf spheres scanned from a ring of views
// into a semantic map (exact depth and labels, no noise).

#include <cmath>
#include <vector>

#include "../mapping/synthetic.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/nbv/nbv_params.h"
#include "canopy/nbv/voxel_index.h"
#include "canopy/perception/semantic_extractor.h"

namespace canopy::nbv_test {

inline const Vec3 kFruitA(0.5, 0.0, 1.0);
inline const Vec3 kFruitB(0.5, 0.3, 1.1);

inline std::vector<synth::Sphere> scene_spheres() {
  return {{kFruitA, 0.04, 2, 0}, {kFruitB, 0.035, 2, 1}, {Vec3(0.56, 0.1, 1.02), 0.05, 1},
          {Vec3(0.45, -0.12, 0.95), 0.05, 1}};
}

/// The scene mapped from `views` cameras on an arc in front of it.
inline mapping::SemanticOcTree scanned_map(int views = 4) {
  mapping::SemanticMapParams p;
  p.threads = 1;
  mapping::SemanticOcTree map(p, SemanticClasses{});
  mapping::ScanInserter ins(map);
  CameraIntrinsics K;
  const auto spheres = scene_spheres();
  for (int v = 0; v < views; ++v) {
    const double a = -0.6 + 1.2 * v / std::max(1, views - 1);
    const Vec3 eye = Vec3(0.5, 0.15, 1.0) + 0.45 * Vec3(-std::cos(a), std::sin(a), 0.1);
    const LabelledFrame f = synth::render_spheres(K, synth::look_at(eye, Vec3(0.5, 0.15, 1.0)), spheres);
    ins.insert(perception::depth_to_cloud(K, f.T_world_camera, f.depth_m, f.class_id, 3));
  }
  return map;
}

// The shape planner's scene (shape_test, view_features_test): one fruit mapped from the front
// only, so its back half is predicted, not seen; optionally a leaf beside its back on +y.
inline const Vec3 kShapeFruit(0.5, 0.0, 1.0);
inline constexpr double kShapeRadius = 0.04;
// The leaf beside and behind the fruit on the +y side (azimuth ~40 deg seen from the fruit).
inline const Vec3 kShapeLeaf = kShapeFruit + 0.11 * Vec3(std::cos(0.7), std::sin(0.7), 0.0);

// The scene mapped from two cameras in front of it (-x side), one of them a little to +y so
// the leaf's face towards the fruit is mapped too.
inline mapping::SemanticOcTree front_map(bool with_leaf) {
  mapping::SemanticMapParams p;
  p.threads = 1;
  mapping::SemanticOcTree map(p, SemanticClasses{});
  mapping::ScanInserter ins(map);
  CameraIntrinsics K;
  std::vector<synth::Sphere> spheres = {{kShapeFruit, kShapeRadius, 2, 0}};
  if (with_leaf) spheres.push_back({kShapeLeaf, 0.06, 1});
  for (const Vec3& eye : {Vec3(0.1, 0.0, 1.0), Vec3(0.15, 0.2, 1.05)}) {
    const LabelledFrame f = synth::render_spheres(K, synth::look_at(eye, kShapeFruit), spheres);
    // Several scans: fruit voxels pass the clustering's log-odds threshold.
    for (int i = 0; i < 3; ++i) ins.insert(perception::depth_to_cloud(K, f.T_world_camera, f.depth_m, f.class_id, 3));
  }
  return map;
}

/// The scene's map, its voxel index, default settings and camera.
struct Fixture {
  mapping::SemanticOcTree map = scanned_map();
  nbv::VoxelIndex index{map};
  nbv::NbvParams params;
  CameraIntrinsics K;
};

}  // namespace canopy::nbv_test
