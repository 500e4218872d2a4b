#pragma once
// Zaenker et al.'s ROI viewpoint planner ("frontier"), as their current code implements it
// (docs/background/frontier_baseline.md; Zaenker et al., ICRA 2021, Eruvae/roi_viewpoint_planner):
// ROI contour targets (free voxels next to ROI voxels with an unknown neighbour) and
// exploration targets (free voxels with an unknown and an occupied neighbour), up to
// max_targets each drawn with replacement; cameras at U(min, max) m from the target; the
// single-ray "ROI vicinity" utility minus distance_cost_per_m per metre of camera travel; ROI
// views when the best ROI utility exceeds roi_utility_threshold, else exploration views;
// position-only workspace test, IK at execution; a batch is tried in utility order until one
// view succeeds (BatchOrder::kUtility).

#include <memory>
#include <vector>

#include "canopy/nbv/planners/frontier/frontier_params.h"
#include "canopy/nbv/view_planner.h"

namespace canopy::nbv {

namespace frontier {
/// Voxel keys of the ROI (occupied, most likely class = target) and frontier targets in `region`.
struct Targets {
  std::vector<Vec3> roi_contour;   ///< Free non-ROI voxels 6-adjacent to ROI with an unknown 6-neighbour.
  std::vector<Vec3> exploration;   ///< Free voxels with an unknown and an occupied 6-neighbour.
  std::vector<Vec3> exploration_normals;  ///< Away from the occupied neighbours, unit.
  std::vector<Vec3> roi;           ///< ROI voxel centres.
};
Targets find_targets(const VoxelIndex& index, const Eigen::AlignedBox3d& region);
/// Inflated ROI value at `p`: 1 at an ROI voxel, falling linearly to 0 at `radius_m`.
class InflatedRoi {
 public:
  InflatedRoi(const std::vector<Vec3>& roi, const Eigen::AlignedBox3d& region, double radius_m, double resolution_m);
  double at(const Vec3& p) const;

 private:
  Vec3 origin_ = Vec3::Zero();
  double resolution_ = 0.05;
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  std::vector<float> values_;
};
/// Utility of the ray origin -> target: unknown voxels add unknown_weight + roi_weight *
/// inflated ROI, free ones 0; stops at the first voxel with p > unknown_high; divided by the
/// voxels on the ray.
double ray_utility(const VoxelIndex& index, const InflatedRoi& roi, const FrontierParams& params, const Vec3& origin,
                   const Vec3& target);
/// The smallest rotation of `current` that points its optical axis (z) at `target` from `eye`.
Pose point_at(const Pose& current, const Vec3& eye, const Vec3& target);
/// The planner (registry name "frontier").
std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings);
/// Its registry entry.
ViewPlannerEntry entry();

}  // namespace frontier

}  // namespace canopy::nbv
