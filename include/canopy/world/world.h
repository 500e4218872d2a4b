#pragma once
// A generated world: triangle meshes of every plant part with its semantic class and fruit
// instance, plus the fruit ground truth. Free of MuJoCo; sim/ turns it into an MJCF scene.

#include <cstddef>
#include <limits>
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
  int first_instance = 0;           ///< The instance id its first fruit takes (the next plant's when it has none).
  std::size_t triangles = 0;        ///< Its parts' triangles (kept when the parts are not held).
  /// Its parts are in `parts`. False for a procedural plant of a world generated with its
  /// plants dropped (GenerateOptions): `parts` is empty, World::plant() generates it again.
  bool held = true;
};

/// How generate_world keeps the plants.
struct GenerateOptions {
  /// Once the plants generated hold this many triangles, every procedural plant's parts are
  /// dropped after its ground truth is sampled (its place, size, counts and first instance id
  /// kept): a long world is then held as its ground truth and one plant at a time, and its
  /// consumers take a plant's parts from World::plant(). Infinite: every plant held.
  double drop_plants_from_triangles = std::numeric_limits<double>::infinity();
};

/// A generated greenhouse world.
struct World {
  WorldSpec spec;
  std::vector<Plant> plants;
  GroundTruth truth;

  size_t triangle_count() const;
  /// Whether every plant's parts are held (`Plant::held`).
  bool plants_held() const;
  /// Plant `i` with its parts: the world's own when held, else generated again from the spec,
  /// the same plant bit for bit (generate_plant). Safe to call from several threads; the plant
  /// generated lives as long as the pointer.
  std::shared_ptr<const Plant> plant(std::size_t i) const;
};

/// Procedural plant `index` of `spec` standing at `base`, its fruits numbered from
/// `first_instance`: what generate_world makes for that slot (each plant draws from its own
/// seed), so a plant can be generated alone when it is needed.
Plant generate_plant(const WorldSpec& spec, int index, const Vec3& base, int first_instance);

/// One line per plant whose drawn fruits did not all fit without overlapping ("plant 3: 12
/// of 20 fruits fitted"); empty when every fruit was placed.
std::vector<std::string> unplaced_fruit_notes(const World& world);

/// Samples every fruit's surface uniformly by area, about spec.gt_point_spacing_m apart.
GroundTruth sample_ground_truth(const World& world);
/// Appends the ground truth of `plant`'s fruits to `truth` (sample_ground_truth's, one plant).
void sample_plant_truth(const WorldSpec& spec, const Plant& plant, GroundTruth* truth);

/// Generates all plants of `spec` from its seed (same seed, same world, bit for bit); with
/// `options`, a long world's plants are dropped after their ground truth is sampled.
World generate_world(const WorldSpec& spec, const GenerateOptions& options = {});

}  // namespace canopy::world
