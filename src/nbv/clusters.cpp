#include "canopy/nbv/clusters.h"

#include <algorithm>

#include "canopy/common/point_kdtree.h"

namespace canopy::nbv {

std::vector<int> dbscan(const std::vector<Vec3>& points, double epsilon_m, int min_points, int* cluster_count) {
  std::vector<int> label(points.size(), -2);  // -2 unvisited, -1 noise
  int clusters = 0;
  if (points.empty()) {
    if (cluster_count) *cluster_count = 0;
    return {};
  }
  const PointKdTree tree(points);
  std::vector<std::pair<std::size_t, double>> nb;
  std::vector<std::size_t> queue;
  auto neighbours = [&](std::size_t i) {
    tree.within(points[i], epsilon_m, &nb);  // nearest first: a deterministic order
    return nb.size();
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (label[i] != -2) continue;
    if (neighbours(i) < std::size_t(min_points)) {
      label[i] = -1;
      continue;
    }
    const int c = clusters++;
    label[i] = c;
    queue.clear();
    for (const auto& n : nb)
      if (n.first != i) queue.push_back(n.first);
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::size_t j = queue[q];
      if (label[j] == -1) label[j] = c;  // border point
      if (label[j] != -2) continue;
      label[j] = c;
      if (neighbours(j) >= std::size_t(min_points))
        for (const auto& n : nb)
          if (label[n.first] < 0) queue.push_back(n.first);
    }
  }
  if (cluster_count) *cluster_count = clusters;
  return label;
}

std::vector<Vec3> cluster_points(const mapping::SemanticOcTree& map, const ClusterParams& params,
                                 const Eigen::AlignedBox3d* region) {
  std::vector<Vec3> pts;
  const int target = map.classes().target_index();
  const auto keep = [&](const mapping::SemanticState& s) {
    return s.most_likely_class() == target && double(s.top_logodds()) > params.min_logodds;
  };
  const auto add = [&](const octomap::OcTreeKey& key, const mapping::SemanticState&) {
    const Vec3 c = map.center_of(key);
    if (!region || region->contains(c)) pts.push_back(c);
  };
  // Only the region's part of the tree is walked (a voxel whose centre lies in the region has a
  // key in [key(min), key(max)]; one key of slack each side); the order is the whole walk's.
  octomap::OcTreeKey lo, hi;
  if (region && map.key_of(region->min(), &lo) && map.key_of(region->max(), &hi)) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = static_cast<octomap::key_type>(lo[a] > 0 ? lo[a] - 1 : 0);
      hi[a] = static_cast<octomap::key_type>(hi[a] < 0xffff ? hi[a] + 1 : 0xffff);
    }
    map.for_each_voxel_in_keys_if(lo, hi, keep, add);
  } else {
    map.for_each_voxel_if(keep, add);
  }
  return pts;
}

std::vector<Cluster> clusters_of_points(const std::vector<Vec3>& pts, const ClusterParams& params) {
  int n = 0;
  const std::vector<int> label = dbscan(pts, params.epsilon_m, params.min_points, &n);
  std::vector<Cluster> out(static_cast<std::size_t>(n));
  for (auto& c : out) {
    c.min = Vec3::Constant(1e300);
    c.max = Vec3::Constant(-1e300);
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (label[i] < 0) continue;
    Cluster& c = out[static_cast<std::size_t>(label[i])];
    c.centroid += pts[i];
    c.min = c.min.cwiseMin(pts[i]);
    c.max = c.max.cwiseMax(pts[i]);
    ++c.voxels;
  }
  for (auto& c : out) c.centroid /= double(c.voxels);
  std::stable_sort(out.begin(), out.end(), [](const Cluster& a, const Cluster& b) { return a.voxels > b.voxels; });
  return out;
}

std::vector<Cluster> find_clusters(const mapping::SemanticOcTree& map, const ClusterParams& params,
                                   const Eigen::AlignedBox3d* region) {
  return clusters_of_points(cluster_points(map, params, region), params);
}

}  // namespace canopy::nbv
