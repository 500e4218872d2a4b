#pragma once
// Scoring one view (paper Methods (iii)): its ray set cast through the voxel index, a gain
// summed over the rays. Every planner that scores views by a gain uses it (ours, global,
// the candidate audit, `canopy bench gain`).
//
// Bad input gives defined results with a reason, never NaN: a camera inside an occupied voxel,
// outside the map, a target behind the camera or a window with no ray -> that view scores 0
// with its status.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "canopy/common/camera.h"
#include "canopy/nbv/candidates.h"
#include "canopy/nbv/gains.h"
#include "canopy/nbv/ray_sets.h"
#include "canopy/nbv/voxel_index.h"

namespace canopy::nbv {

/// Why a view scored what it did.
enum class ViewStatus { kOk, kNoRays, kTargetBehind, kInsideOccupied, kOutsideMap };
const char* to_string(ViewStatus s);

/// Score of one view.
struct ViewScore {
  double gain = 0.0;
  ViewStatus status = ViewStatus::kOk;
  std::size_t rays = 0;          ///< Rays cast.
  std::size_t rays_outside = 0;  ///< Rays with an end outside the map (skipped).
  std::size_t voxels = 0;        ///< Voxels visited.
  double ms = 0.0;               ///< Ray casting and gain time.
};

/// Scores views against one voxel index; holds per-thread scratch (no allocation per ray).
class ViewEvaluator {
 public:
  ViewEvaluator(const VoxelIndex& index, const CameraIntrinsics& intrinsics, const RayParams& params);

  /// Gain of the view at T_world_camera looking at `target` with ray set `rays`.
  ViewScore evaluate(const Pose& T_world_camera, const Vec3& target, const GainFunction& gain,
                     const RaySetEntry& rays, std::uint64_t view_seed);
  /// Several gains of one view from one cast of its rays: out[i] = evaluate(..., *gains[i], ...).gain
  /// (bit for bit); `each_ray`, when set, is also given every ray's voxels. Returns the status.
  /// `bricks`, when given, is appended the brick keys of every voxel read (the camera's and the
  /// rays'): the result depends on the map through those bricks only.
  ViewStatus evaluate_all(const Pose& T_world_camera, const Vec3& target, const std::vector<const GainFunction*>& gains,
                          const RaySetEntry& rays, std::uint64_t view_seed, double* out,
                          const std::function<void(const RayVoxel*, std::size_t)>& each_ray = nullptr,
                          std::vector<std::uint64_t>* bricks = nullptr);
  /// The same through the slow reference traversal (computeRayKeys + a tree search per key,
  /// voxel values computed from the tree's states).
  ViewScore evaluate_reference(const Pose& T_world_camera, const Vec3& target, const GainFunction& gain,
                               const RaySetEntry& rays, std::uint64_t view_seed);

  /// The ray ends of a view (world frame) as evaluate() casts them; false with a status when
  /// the view is not scored.
  bool ray_segments(const Pose& T_world_camera, const Vec3& target, const RaySetEntry& rays,
                    std::vector<Vec3>* ends, ViewStatus* status);

 private:
  bool precheck(const Pose& T_world_camera, const Vec3& target, ViewScore* score) const;

  const VoxelIndex& index_;
  CameraIntrinsics intrinsics_;
  RayParams params_;
  std::vector<Vec2> pixels_;
  std::vector<Vec3> ends_;
  std::vector<RayVoxel> buffer_;
  std::vector<double> sums_;
  octomap::KeyRay key_ray_;
  std::vector<ReferenceVoxel> ref_voxels_;
  std::vector<VoxelInfo> ref_infos_;
};

/// A scored candidate.
struct ScoredView {
  Candidate candidate;
  ViewScore score;
};

/// Candidate filter (e.g. the arm's workspace filter); true keeps the candidate. It may move
/// the candidate (T_world_camera, shift_m) and attach its IK solution (has_q, q): the moved
/// pose is the one scored, and the one the robot will visit.
using CandidateFilter = std::function<bool(Candidate*)>;

/// Told every scored candidate (for recording; it cannot change the plan).
using CandidateObserver = std::function<void(const ScoredView&)>;

}  // namespace canopy::nbv
