#pragma once
// Job: the mapping benchmark (`canopy bench map`): semantic insertion against OctoMap's plain
// insertPointCloud (discretize = true) on the same labelled clouds of rendered frames of a
// world, in the same run; then a full frame of a wall 0.9 m away (every pixel valid), where the
// dense part of the work and the second core count (docs/background/speed_anchors.md).

#include <cstddef>
#include <string>

#include "canopy/settings/settings.h"

namespace canopy::jobs {

/// What bench_map measures.
struct BenchMapParams {
  std::string world_file = "worlds/default.yaml";
  settings::MappingSettings mapping;  ///< The settings' mapping section.
  std::string views = "ring";         ///< Camera poses: 'ring', 'aisle' or a file of poses.
  int frames = 32;                    ///< Frames to insert, spread over the views.
  int repeats = 3;                    ///< Runs over all frames, averaged.
};

/// One way of inserting: ms per frame (and the semantic insertion's phases), nodes at the end.
struct InsertTiming {
  double ms = 0.0;
  double filter_ms = 0.0, raycast_ms = 0.0, update_ms = 0.0;  ///< Semantic insertion's phases.
  std::size_t nodes = 0;
};

/// The four ways of inserting one set of clouds.
struct InsertTimings {
  InsertTiming octomap;         ///< OctoMap insertPointCloud up to the map's max range.
  InsertTiming semantic;        ///< Semantic, the map's ray range, all cores.
  InsertTiming semantic_one;    ///< The same on one thread.
  InsertTiming semantic_full;   ///< Semantic with the ray range = OctoMap's (the max range).
  double points_per_frame = 0.0;  ///< Mean points of a frame.
};

/// What it measured.
struct BenchMapResult {
  std::string world_name;
  int width_px = 0, height_px = 0;
  int frames = 0;
  double resolution_m = 0.0, max_range_m = 0.0, ray_range_m = 0.0;
  InsertTimings rendered;       ///< The rendered frames.
  InsertTimings wall;           ///< 8 frames of a wall 0.9 m away.
};

/// Renders the frames and times the insertions. InputError for a bad world or views.
BenchMapResult bench_map(const BenchMapParams& params);

}  // namespace canopy::jobs
