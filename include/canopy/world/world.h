#pragma once
// A generated world: triangle meshes of every plant part with its semantic class and fruit
// instance, plus the fruit ground truth. Free of MuJoCo; sim/ turns it into an MJCF scene.

#include <memory>
#include <string>
#include <vector>

#include "canopy/common/frame.h"
#include "canopy/world/ground_truth.h"
#include "canopy/world/mesh.h"
#include "canopy/world/texture.h"
#include "canopy/world/world_spec.h"

namespace canopy::world {

/// One piece of plant geometry (a stem, a leaf, a fruit, ...), in world coordinates.
struct PlantPart {
  std::string name;                 ///< Unique, e.g. "p3_leaf_12".
  std::string kind;                 ///< "stem", "petiole", "leaf", "peduncle", "fruit".
  std::string material;             ///< Imported plants: the model's material ("" for procedural parts).
  int class_id = 0;                 ///< Index into WorldSpec::classes.
  int instance_id = kNoInstance;    ///< Fruit instance id (fruits only).
  std::string fruit_color;          ///< Fruits only: "red", "yellow", ...
  std::string fruit_shape;          ///< Fruits only: "blocky" or "conical".
  bool fruit_target = true;         ///< Fruits only: ripe, counted by the metrics.
  /// Fruits of imported plants: their folder's ground truth (world frame) and area, used
  /// instead of sampling the mesh.
  bool has_truth_points = false;
  std::vector<Vec3> truth_points;
  double truth_area_m2 = 0.0;
  float rgba[4] = {0.f, 0.f, 0.f, 1.f};
  TriMesh mesh;                     ///< World-frame vertices.
  /// Textured parts of imported plants: the texture (shared), its PNG file (absolute path)
  /// and the texture coordinates of every face of `mesh`.
  std::shared_ptr<const Image<Rgb8>> texture;
  std::string texture_file;
  std::vector<FaceUv> uv;
};

/// One plant: its base position on the ground and its parts.
struct Plant {
  int index = 0;
  Vec3 base_position = Vec3::Zero();
  double height_m = 0.0;
  std::string import_dir;           ///< Imported plants: their plant folder ("" for procedural).
  std::vector<PlantPart> parts;
  int fruits_drawn = 0;             ///< Procedural plants: fruits drawn from the spec's range.
  int fruits_placed = 0;            ///< ... of which fitted without overlapping (the rest are dropped).
};

/// A generated greenhouse world.
struct World {
  WorldSpec spec;
  std::vector<Plant> plants;
  GroundTruth truth;

  size_t triangle_count() const;
};

/// One line per plant whose drawn fruits did not all fit without overlapping ("plant 3: 12
/// of 20 fruits fitted"); empty when every fruit was placed.
std::vector<std::string> unplaced_fruit_notes(const World& world);

/// Samples every fruit's surface uniformly by area, about spec.gt_point_spacing_m apart.
GroundTruth sample_ground_truth(const World& world);

/// Generates all plants of `spec` from its seed (same seed, same world, bit for bit).
World generate_world(const WorldSpec& spec);

}  // namespace canopy::world
