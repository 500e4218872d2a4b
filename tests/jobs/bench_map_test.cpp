// The mapping benchmark (jobs/bench_map.h) on a few frames: every way of inserting maps the
// same frames; one thread and all cores build the same tree, and OctoMap's longer rays a
// larger one than the semantic map's ray range.

#include <gtest/gtest.h>

#include "canopy/jobs/bench_map.h"

namespace canopy::jobs {
namespace {

TEST(BenchMap, TheWaysOfInsertingAgreeOnWhatTheyBuild) {
  BenchMapParams p;
  p.world_file = "worlds/small.yaml";
  p.frames = 2;
  p.repeats = 1;
  const BenchMapResult r = bench_map(p);
  EXPECT_EQ(r.frames, 2);
  EXPECT_EQ(r.resolution_m, p.mapping.map.resolution_m);
  for (const InsertTimings* t : {&r.rendered, &r.wall}) {
    EXPECT_GT(t->points_per_frame, 0.0);
    EXPECT_GT(t->octomap.nodes, 0u);
    EXPECT_EQ(t->semantic.nodes, t->semantic_one.nodes);  // threads change the time, not the tree
    EXPECT_GE(t->semantic_full.nodes, t->semantic.nodes);  // longer free rays reach more voxels
    EXPECT_GT(t->semantic.ms, 0.0);
  }
  EXPECT_EQ(r.wall.points_per_frame, double(r.width_px) * r.height_px);  // every pixel of the wall is valid
}

}  // namespace
}  // namespace canopy::jobs
