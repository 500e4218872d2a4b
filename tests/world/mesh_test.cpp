// Triangle meshes (world/mesh.h): the primitives are closed and outward (a tube's volume is the
// cylinder's), and the clean-up of imported meshes (weld, compact, cluster) against hand-counted
// results.

#include <gtest/gtest.h>

#include <cmath>

#include "canopy/world/mesh.h"

namespace canopy::world {
namespace {

TEST(Mesh, PrimitivesAreClosedAndOutward) {
  const TriMesh tube = make_tube({Vec3(0, 0, 0), Vec3(0, 0, 1)}, {0.1, 0.1}, 64);
  EXPECT_NEAR(tube.volume(), M_PI * 0.01 * 1.0, 0.01 * M_PI * 0.01);
  const std::vector<Vec2> profile = {{0, 0}, {0.5, -0.25}, {0.5, -0.75}, {0, -1}};
  const TriMesh rev = make_lobed_revolution(profile, 32, 0, 0.0);
  EXPECT_GT(rev.volume(), 0.0);
}

// The clean-up of imported meshes: welding within a tolerance, degenerate triangles counted,
// unused vertices dropped, vertex clustering collapsing faces.
TEST(Mesh, WeldCompactAndClusterVertices) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(1, 1, 0), jitter(1e-7, 0, 0);
  long degenerate = 0;
  std::vector<size_t> kept;
  const TriMesh m = weld_triangles({{a, b, c}, {b + jitter, d, c}, {a, a + jitter, d}}, 1e-6, &degenerate, &kept);
  EXPECT_EQ(m.vertices.size(), 4u);  // b and its jittered copy merged
  EXPECT_EQ(m.faces.size(), 2u);
  EXPECT_EQ(degenerate, 1);          // a, a + jitter, d collapses
  EXPECT_EQ(kept, (std::vector<size_t>{0, 1}));
  EXPECT_NEAR(m.area(), 1.0, 1e-12);
  TriMesh unused = m;
  unused.vertices.push_back(Vec3(5, 5, 5));
  EXPECT_EQ(compact(unused).vertices.size(), 4u);
  // A 2 m cell puts every vertex in one cell (the square lies in [0, 1]^2): nothing is left.
  EXPECT_TRUE(cluster_vertices(m, 2.0).faces.empty());
  // A 1 mm cell changes nothing.
  EXPECT_EQ(cluster_vertices(m, 0.001).faces.size(), 2u);
}

}  // namespace
}  // namespace canopy::world
