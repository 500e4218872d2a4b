#pragma once
// Would colour segmentation see a plant's fruit, and nothing else as fruit? For every material
// of the scene (the ground's, the procedural plants' part kinds, imported plants' materials,
// the robot's colours), the share of its surface (texture: by UV area over its texels; flat
// colours: by area) that the
// HSV bands label with each class, and what is wrong with that: a target-fruit material that
// is mostly not labelled the target class (colour segmentation cannot find those fruit), or
// a material of another class of which much is labelled the target class (false fruit).
// The colours checked are the material's own (texture or flat), before lighting.

#include <string>
#include <vector>

#include "canopy/common/classes.h"
#include "canopy/perception/color_segmentation.h"
#include "canopy/world/plant_import.h"
#include "canopy/world/world.h"

namespace canopy::evaluation {

/// A target-fruit material must be at least this share target-coloured.
constexpr double kMinTargetColourShare = 0.5;
/// A material of another class may be at most this share target-coloured.
constexpr double kMaxOtherTargetColourShare = 0.25;

/// What colour segmentation makes of one material.
struct MaterialSegmentation {
  std::string owner;          ///< What it belongs to: a plant folder (or model file), "procedural plants", "ground", "robot".
  std::string material;
  std::string class_name;     ///< Its class in the plant.
  bool target = true;         ///< False for unripe fruit (not scored; never a problem).
  bool textured = false;      ///< Its colours are a texture's (else one flat colour).
  std::vector<double> share;  ///< Per class of the class list: share of its surface labelled so.
  std::string problem;        ///< Empty when colour segmentation sees it as it should.

  /// "fruit 0.97, leaf 0.00, background 0.03" (classes with a share, largest first).
  std::string shares(const SemanticClasses& classes) const;
};

/// Checks every material of `parts` (one plant, parts of one material checked together).
std::vector<MaterialSegmentation> check_color_segmentation(const std::vector<world::ImportedPart>& parts,
                                                           const std::string& plant,
                                                           const perception::ColorSegmentationParams& params,
                                                           const SemanticClasses& classes);

/// A flat-coloured material that is no plant's: the ground's, the robot's, anything added.
struct FlatMaterial {
  std::string owner;       ///< "ground", "robot", ...
  std::string material;
  std::string class_name;  ///< The class its pixels truly carry.
  float rgba[4] = {0.f, 0.f, 0.f, 1.f};
};

/// Checks flat-coloured materials.
std::vector<MaterialSegmentation> check_color_segmentation(const std::vector<FlatMaterial>& materials,
                                                           const perception::ColorSegmentationParams& params,
                                                           const SemanticClasses& classes);

/// The ground's materials of a world (spec.ground): the film and, when there is one, the path.
std::vector<FlatMaterial> ground_materials(const world::WorldSpec& spec);

/// Every material of a world: the ground's, one per part kind of the procedural plants
/// (fruits: one per colour), and every imported plant's (each plant folder once).
std::vector<MaterialSegmentation> check_color_segmentation(const world::World& world,
                                                           const perception::ColorSegmentationParams& params);

}  // namespace canopy::evaluation
