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

// DBSCAN as written down (every pair's distance, neighbours in index order, a cluster grown by
// a plain queue): the slow reference of dbscan().
std::vector<int> dbscan_reference(const std::vector<Vec3>& pts, double eps, int min_points, int* count) {
  const std::size_t n = pts.size();
  std::vector<std::vector<std::size_t>> nb(n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      double d2 = 0.0;
      for (int a = 0; a < 3; ++a) d2 += (pts[i][a] - pts[j][a]) * (pts[i][a] - pts[j][a]);
      if (d2 < eps * eps) nb[i].push_back(j);
    }
  std::vector<int> label(n, -2);
  int c = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (label[i] != -2) continue;
    if (nb[i].size() < std::size_t(min_points)) {
      label[i] = -1;
      continue;
    }
    label[i] = c;
    std::vector<std::size_t> queue(nb[i].begin(), nb[i].end());
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::size_t j = queue[q];
      if (label[j] == -1) label[j] = c;
      if (label[j] != -2) continue;
      label[j] = c;
      if (nb[j].size() >= std::size_t(min_points)) queue.insert(queue.end(), nb[j].begin(), nb[j].end());
    }
    ++c;
  }
  *count = c;
  return label;
}

// Clouds of voxel centres (blobs that touch through thin bridges, surfaces, scattered noise):
// the same labels as the reference, point for point.
TEST(Clusters, DbscanLabelsAsTheReference) {
  Rng rng(47);
  const double res = 0.015;
  int compared = 0;
  for (int cloud = 0; cloud < 40; ++cloud) {
    std::vector<Vec3> pts;
    const int blobs = 1 + cloud % 6;
    for (int b = 0; b < blobs; ++b) {
      const Vec3 centre(rng.uniform(0.0, 0.4), rng.uniform(0.0, 0.4), rng.uniform(0.0, 0.4));
      const int n = int(rng.uniform(5, 150));
      for (int i = 0; i < n; ++i) {
        const Vec3 p = centre + rng.uniform(0.01, 0.05) * Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
        pts.push_back(((p / res).array().floor() + 0.5).matrix() * res);  // a voxel centre
      }
    }
    for (int i = 0; i < 30; ++i) pts.push_back(Vec3(rng.uniform(0.0, 0.4), rng.uniform(0.0, 0.4), rng.uniform(0.0, 0.4)));
    for (const int min_points : {3, 5}) {
      int n = -1, n_ref = -2;
      const std::vector<int> label = dbscan(pts, 0.05, min_points, &n);
      ASSERT_EQ(label, dbscan_reference(pts, 0.05, min_points, &n_ref)) << "cloud " << cloud;
      ASSERT_EQ(n, n_ref);
      compared += n;
    }
  }
  EXPECT_GT(compared, 100);
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
