#include <gtest/gtest.h>

#include "canopy/common/random.h"
#include "canopy/nbv/clusters.h"
#include "scene.h"

using namespace canopy;
using namespace canopy::nbv;

TEST(Clusters, DbscanSeparatesBlobsAndNoise) {
  Rng rng(5);
  std::vector<Vec3> pts;
  for (int i = 0; i < 50; ++i) pts.push_back(Vec3(0, 0, 0) + 0.02 * Vec3(rng.normal(), rng.normal(), rng.normal()));
  for (int i = 0; i < 30; ++i) pts.push_back(Vec3(1, 0, 0) + 0.02 * Vec3(rng.normal(), rng.normal(), rng.normal()));
  pts.push_back(Vec3(0.5, 0.5, 0.5));  // isolated: noise
  int n = 0;
  const std::vector<int> label = dbscan(pts, 0.05, 3, &n);
  EXPECT_EQ(n, 2);
  EXPECT_EQ(label.back(), -1);
  for (int i = 1; i < 50; ++i) EXPECT_EQ(label[i], label[0]);
  for (int i = 51; i < 80; ++i) EXPECT_EQ(label[i], label[50]);
  EXPECT_NE(label[0], label[50]);
  ClusterParams p;
  const auto clusters = clusters_of_points(pts, p);
  ASSERT_EQ(clusters.size(), 2u);
  EXPECT_GE(clusters[0].voxels, clusters[1].voxels);  // largest first
  EXPECT_LT(clusters[0].centroid.norm(), 0.02);
  EXPECT_LT((clusters[1].centroid - Vec3(1, 0, 0)).norm(), 0.02);
  EXPECT_TRUE((clusters[0].min.array() <= clusters[0].centroid.array()).all());
  EXPECT_TRUE((clusters[0].max.array() >= clusters[0].centroid.array()).all());
}

TEST(Clusters, TooFewPointsAreNoise) {
  int n = -1;
  EXPECT_TRUE(dbscan({}, 0.05, 3, &n).empty());
  EXPECT_EQ(n, 0);
  const std::vector<int> label = dbscan({Vec3(0, 0, 0), Vec3(0.01, 0, 0)}, 0.05, 3, &n);
  EXPECT_EQ(n, 0);
  EXPECT_EQ(label, (std::vector<int>{-1, -1}));
}

// The scanned scene has two fruit spheres far apart: two clusters near their centres.
TEST(Clusters, FindsTheFruitsOfAMap) {
  const mapping::SemanticOcTree map = nbv_test::scanned_map();
  const auto clusters = find_clusters(map, ClusterParams{});
  ASSERT_EQ(clusters.size(), 2u);
  std::vector<Vec3> c = {clusters[0].centroid, clusters[1].centroid};
  if ((c[0] - nbv_test::kFruitA).norm() > (c[1] - nbv_test::kFruitA).norm()) std::swap(c[0], c[1]);
  // Seen from one side: the centroid of the visible cap lies within a radius of the centre.
  EXPECT_LT((c[0] - nbv_test::kFruitA).norm(), 0.04);
  EXPECT_LT((c[1] - nbv_test::kFruitB).norm(), 0.035);
  // A region around one fruit keeps only that one.
  const Eigen::AlignedBox3d box(nbv_test::kFruitA - Vec3::Constant(0.1), nbv_test::kFruitA + Vec3::Constant(0.1));
  EXPECT_EQ(find_clusters(map, ClusterParams{}, &box).size(), 1u);
}

// The log-odds threshold is strict: one hit (l = 1.0) does not qualify, two hits do.
TEST(Clusters, LogOddsThreshold) {
  mapping::SemanticOcTree map(mapping::SemanticMapParams{}, SemanticClasses{});
  std::vector<octomap::OcTreeKey> keys;
  for (int i = 0; i < 4; ++i) {
    octomap::OcTreeKey k;
    ASSERT_TRUE(map.key_of(Vec3(0.5 + 0.015 * i, 0, 1), &k));
    map.update_hit(k, 2);
    keys.push_back(k);
  }
  EXPECT_TRUE(find_clusters(map, ClusterParams{}).empty());
  for (const auto& k : keys) map.update_hit(k, 2);
  const auto clusters = find_clusters(map, ClusterParams{});
  ASSERT_EQ(clusters.size(), 1u);
  EXPECT_EQ(clusters[0].voxels, 4u);
  // leaf voxels never cluster
  mapping::SemanticOcTree leaves(mapping::SemanticMapParams{}, SemanticClasses{});
  for (const auto& k : keys) {
    leaves.update_hit(k, 1);
    leaves.update_hit(k, 1);
  }
  EXPECT_TRUE(find_clusters(leaves, ClusterParams{}).empty());
}
