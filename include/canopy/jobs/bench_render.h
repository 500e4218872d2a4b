#pragma once
// Job: the rendering benchmark (`canopy bench render`): time per frame (RGB + depth, and with
// the labels) along a world's aisle, with frustum culling and with the full scene.

#include <string>
#include <vector>

namespace canopy::jobs {

/// What bench_render measures.
struct BenchRenderParams {
  std::string world_file = "worlds/default.yaml";
  int frames = 50;       ///< Views along the aisle, looking at both rows in turn.
  bool shadows = false;  ///< Shadows in the RGB pass.
};

/// One way of drawing the frames.
struct RenderTiming {
  bool culling = true;
  double geoms = 0.0, triangles = 0.0;     ///< Drawn per frame, on average.
  double rgbd_ms = 0.0, labelled_ms = 0.0;  ///< Per frame: RGB + depth, RGB + depth + labels.
};

/// What it measured.
struct BenchRenderResult {
  std::string world_name;
  std::size_t plants = 0, plant_triangles = 0;
  int width_px = 0, height_px = 0, frames = 0;
  int scene_geoms = 0;
  std::vector<RenderTiming> timings;  ///< With frustum culling, then the full scene.
};

/// Renders the frames (after one to warm up). InputError for a bad world file.
BenchRenderResult bench_render(const BenchRenderParams& params);

}  // namespace canopy::jobs
