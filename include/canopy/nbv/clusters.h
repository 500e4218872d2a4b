#pragma once
// Fruit clusters (paper Methods (ii)-(iii); docs/background/nbv_pipeline.md): DBSCAN over the centres of
// voxels whose most likely class is the target with log-odds above a threshold.

#include <Eigen/Geometry>

#include <vector>

#include "canopy/common/types.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/nbv/nbv_params.h"

namespace canopy::nbv {

/// One cluster of target voxels.
struct Cluster {
  Vec3 centroid = Vec3::Zero();    ///< Mean of the member voxel centres.
  Vec3 min = Vec3::Zero();         ///< Axis-aligned extent of the members.
  Vec3 max = Vec3::Zero();
  std::size_t voxels = 0;          ///< Member voxels.
};

/// DBSCAN labels of `points`: label per point (-1 = noise), clusters numbered 0.. in order of
/// their first core point. `min_points` counts the point itself. Deterministic.
std::vector<int> dbscan(const std::vector<Vec3>& points, double epsilon_m, int min_points, int* cluster_count);

/// Centres of the voxels that take part in clustering: most likely class = the map's target
/// and its log-odds > params.min_logodds; only inside `region` when given (pruned blocks expanded).
std::vector<Vec3> cluster_points(const mapping::SemanticOcTree& map, const ClusterParams& params,
                                 const Eigen::AlignedBox3d* region = nullptr);

/// Clusters of the map's target voxels (empty when there are none), largest first.
std::vector<Cluster> find_clusters(const mapping::SemanticOcTree& map, const ClusterParams& params,
                                   const Eigen::AlignedBox3d* region = nullptr);

/// Clusters of given points (the DBSCAN part of find_clusters), largest first.
std::vector<Cluster> clusters_of_points(const std::vector<Vec3>& points, const ClusterParams& params);

}  // namespace canopy::nbv
