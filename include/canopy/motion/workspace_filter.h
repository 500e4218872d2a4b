#pragma once
// The paper's candidate-view filter (Methods iii, "Filtering out candidate viewpoints"):
// camera positions from forward kinematics over many joint combinations form the arm's
// workspace point set, kept in a KD-tree in the arm-base frame (so one set serves every
// base pose). A candidate view is moved along its viewing direction into the workspace
// (nearest-neighbour membership); views whose viewing line misses the workspace are
// discarded, and survivors must have an IK solution (optionally a collision-free one).

#include <cstdint>
#include <memory>
#include <vector>

#include "canopy/common/params.h"
#include "canopy/common/point_kdtree.h"
#include "canopy/common/types.h"
#include "canopy/motion/robot_model.h"

namespace canopy {
class YamlReader;
}

namespace canopy::motion {

class CollisionChecker;

/// Workspace filter settings (configs/motion.yaml, section "workspace").
struct WorkspaceParams {
  int samples = 50000;                 ///< Random joint combinations for the point set.
  std::uint64_t seed = 1;              ///< Seed of those samples.
  double membership_radius_m = 0.03;   ///< In the workspace: a sample within this distance.
  double min_camera_height_m = 0.05;   ///< Samples with the camera lower than this are dropped.
  double max_forward_shift_m = 0.15;   ///< Furthest move towards the target along the view.
  double max_backward_shift_m = 0.25;  ///< Furthest move away from the target.
  double shift_step_m = 0.01;          ///< Spacing of the positions tried along the view.

  template <class A>
  void visit(A& a) {
    a("samples", samples, limits::in(100, 10000000), "Random joint combinations for the workspace point set");
    a("seed", seed, limits::non_negative(), "Seed of those samples");
    a("membership_radius_m", membership_radius_m, limits::positive(), "In the workspace: a sample within this [m]");
    a("min_camera_height_m", min_camera_height_m, limits::finite(), "Samples with the camera lower are dropped [m]");
    a("max_forward_shift_m", max_forward_shift_m, limits::non_negative(), "Furthest move towards the target [m]");
    a("max_backward_shift_m", max_backward_shift_m, limits::non_negative(), "Furthest move away from the target [m]");
    a("shift_step_m", shift_step_m, limits::positive(), "Spacing of the positions tried along the view [m]");
  }
  void validate() const { validate_params(*this, "workspace"); }
};

/// Why a candidate view was dropped (or kept).
enum class ViewVerdict {
  kKept,
  kOutsideWorkspace,  ///< The viewing line within the shift range misses the workspace.
  kNoIk,              ///< Workspace points on the line, none with an IK solution.
  kInCollision,       ///< IK solutions exist, all in collision (only with a checker).
  kInvalidInput,      ///< Non-finite pose.
};
const char* to_string(ViewVerdict verdict);

/// A candidate after filtering.
struct FilteredView {
  ViewVerdict verdict = ViewVerdict::kInvalidInput;
  Pose T_world_camera = Pose::Identity();  ///< Moved pose (same orientation) when kept.
  double shift_m = 0.0;                    ///< Move along the viewing direction (+ forward).
  ArmConfig q{};                           ///< Nearest (collision-free) IK solution when kept.
  bool kept() const { return verdict == ViewVerdict::kKept; }
};

/// The arm's workspace point set and the candidate filter. Immutable after construction;
/// queries are thread-safe.
class WorkspaceFilter {
 public:
  WorkspaceFilter(const RobotModel& model, const WorkspaceParams& params);
  ~WorkspaceFilter();
  WorkspaceFilter(WorkspaceFilter&&) noexcept;

  /// Distance from a world point to the nearest workspace sample, for the base at `base`.
  double distance_to_workspace(const BasePose& base, const Vec3& p_world) const;
  bool in_workspace(const BasePose& base, const Vec3& p_world) const {
    return distance_to_workspace(base, p_world) <= params_.membership_radius_m;
  }

  /// Filters one candidate (camera z = viewing direction). `seed` ranks IK solutions;
  /// with a checker, the kept IK solution must also be collision-free.
  FilteredView filter(const BasePose& base, const Pose& T_world_camera, const ArmConfig& seed,
                      const CollisionChecker* checker = nullptr) const;

  /// Workspace samples (camera positions) in the arm-base (DH frame 0) frame.
  const std::vector<Vec3>& points_in_arm() const { return tree_->points(); }
  const WorkspaceParams& params() const { return params_; }
  const RobotModel& model() const { return *model_; }

 private:
  const RobotModel* model_;
  WorkspaceParams params_;
  std::unique_ptr<PointKdTree> tree_;  ///< Workspace points in the arm base frame.
};

}  // namespace canopy::motion
