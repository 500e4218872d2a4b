#pragma once
// Would colour segmentation see a plant's fruit? For every material of an imported plant,
// the share of its surface (texture: by UV area over its texels; flat: all of it) that the
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
  std::string plant;          ///< Plant folder (or model file) it belongs to.
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

/// The same for every imported plant of a world (each plant folder once).
std::vector<MaterialSegmentation> check_color_segmentation(const world::World& world,
                                                           const perception::ColorSegmentationParams& params);

}  // namespace canopy::evaluation
