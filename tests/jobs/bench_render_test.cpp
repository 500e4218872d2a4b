// The rendering benchmark (jobs/bench_render.h) on a few frames: culling draws no more than
// the full scene, and labels cost no less than RGB + depth alone.

#include <gtest/gtest.h>

#include "canopy/jobs/bench_render.h"

namespace canopy::jobs {
namespace {

TEST(BenchRender, CullingDrawsNoMoreThanTheFullScene) {
  BenchRenderParams p;
  p.world_file = "worlds/small.yaml";
  p.frames = 3;
  const BenchRenderResult r = bench_render(p);
  EXPECT_EQ(r.frames, 3);
  EXPECT_EQ(r.plants, 2u);
  EXPECT_GT(r.plant_triangles, 0u);
  ASSERT_EQ(r.timings.size(), 2u);
  const RenderTiming& culled = r.timings[0];
  const RenderTiming& full = r.timings[1];
  EXPECT_TRUE(culled.culling);
  EXPECT_FALSE(full.culling);
  EXPECT_LE(culled.geoms, full.geoms);
  EXPECT_LE(culled.triangles, full.triangles);
  EXPECT_LE(full.geoms, r.scene_geoms);
  for (const RenderTiming& t : r.timings) {
    EXPECT_GT(t.rgbd_ms, 0.0);
    EXPECT_GT(t.labelled_ms, 0.0);
  }
}

}  // namespace
}  // namespace canopy::jobs
