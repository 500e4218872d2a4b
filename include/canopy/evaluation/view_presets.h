#pragma once
// Camera poses for mapping runs with a free-floating camera (`canopy map --views`): presets
// around the plants of a world, or a file of poses.

#include <string>
#include <vector>

#include "canopy/common/camera.h"  // look_at
#include "canopy/common/types.h"
#include "canopy/world/world.h"

namespace canopy::evaluation {

/// The `ring` preset: around each plant, `azimuths` cameras on a horizontal circle of radius
/// `radius_m` at each height (fractions of the plant's height), looking at the plant's axis
/// at the same height. Plants in index order, heights low to high, azimuths from the aisle.
struct RingViews {
  int azimuths = 8;
  double radius_m = 0.4;
  std::vector<double> heights = {0.45, 0.7};
};
std::vector<Pose> ring_views(const world::World& world, const RingViews& ring = {});

/// The `aisle` preset: `per_side` cameras along each row, from the aisle, looking at the row
/// horizontally at `height_m`, `distance_m` in front of the row's centre line.
std::vector<Pose> aisle_views(const world::World& world, int per_side = 8, double distance_m = 0.45,
                              double height_m = 0.7);

/// Reads poses, one per line as "x y z qw qx qy qz" (spaces or commas; '#' starts a comment).
/// Throws InputError naming the file and line.
std::vector<Pose> load_views(const std::string& path);

/// A preset name ("ring", "aisle") or a file of poses.
std::vector<Pose> views_from_spec(const std::string& spec, const world::World& world);

}  // namespace canopy::evaluation
