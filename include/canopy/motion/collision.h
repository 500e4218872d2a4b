#pragma once
// Collision checking with FCL: the robot's collision shapes (from the URDF) against the
// ground, against the current occupancy map (an FCL octree built from the map's occupied
// voxel centres, not the ground truth) and against themselves (non-adjacent links only).
// FCL stays inside collision.cpp; this header is FCL-free.

#include <iosfwd>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "canopy/common/params.h"
#include "canopy/common/types.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/motion/robot_model.h"

namespace canopy {
class YamlReader;
}

namespace canopy::motion {

/// Collision checking settings.
struct CollisionParams {
  /// Robot shapes are inflated by this much against the map and the ground (a safety
  /// margin for map noise and tracking error).
  double environment_padding_m = 0.01;
  /// Inflation for self-collision checks.
  double self_padding_m = 0.0;
  bool check_ground = true;
  double ground_height_m = 0.0;

  template <class A>
  void visit(A& a) {
    a("environment_padding_m", environment_padding_m, limits::non_negative(),
      "Robot shapes are inflated by this much against the map and the ground [m]");
    a("self_padding_m", self_padding_m, limits::non_negative(), "Inflation for self-collision checks [m]");
    a("check_ground", check_ground, "Check the robot against the ground plane");
    a("ground_height_m", ground_height_m, limits::finite(), "Height of the ground plane [m]");
  }
  void validate() const { validate_params(*this, "collision"); }
};

/// The environment as occupied voxels (an FCL octree). Shared by checkers through a
/// shared_ptr, so it lives as long as any checker that reads it. update() changes it in
/// place (incremental, as a map grows view by view); do not update it while another thread
/// runs queries on it.
class CollisionEnvironment {
 public:
  /// Builds the octree from occupied voxel centres on a grid of `resolution_m` (voxel
  /// centres at (k + 1/2) * resolution, as OctoMap places them). Throws InputError on a
  /// non-positive resolution; non-finite centres are skipped.
  static std::shared_ptr<const CollisionEnvironment> from_voxels(const std::vector<Vec3>& centres,
                                                                 double resolution_m);
  /// An environment with no voxel yet, to be filled by update().
  static std::shared_ptr<CollisionEnvironment> empty(double resolution_m);
  ~CollisionEnvironment();
  /// Marks the voxels containing `occupied` as occupied and those containing `freed` as free
  /// (freed first, so a voxel in both ends occupied). Points outside the tree are skipped.
  void update(const std::vector<Vec3>& occupied, const std::vector<Vec3>& freed);
  /// Follows one scan of `map` (mapping::ScanInserter::last_updates() and last_occupancy()):
  /// updated voxels occupied after it enter; hits not occupied, and voxels occupied before it
  /// and no longer, leave. An environment that only ever took the map's occupied voxels holds
  /// none of the others, so they are not looked at.
  void follow_scan(const mapping::SemanticOcTree& map, const std::vector<mapping::VoxelUpdate>& updates,
                   const std::vector<std::uint8_t>& occupancy);
  /// Holds only the octree's subtrees of 64 voxels a side whose x overlaps [x_lo_m, x_hi_m]
  /// (a long row's stretch near the robot, issue 49); the others are written out compactly
  /// (about 5 bytes a node) and put back, as they were, when a later keep_x() holds them again
  /// or update() / follow_scan() changes a voxel of theirs. Queries (the checkers',
  /// clear_robot_volume()) answer as the whole environment's for anything inside the stretch
  /// held (the subtrees inside are untouched, and an inner node's occupancy is the largest of
  /// its children's, so no query inside reads the ones out); a query that reaches beyond it is
  /// an error (CANOPY_CHECK), never a different answer; occupied() answers anywhere but in a
  /// subtree moved out (an error there). Not while another thread queries.
  void keep_x(double x_lo_m, double x_hi_m);
  /// Every subtree back: the tree is the one that took every change without keep_x().
  void keep_all();
  bool windowed() const;
  /// Subtrees written out by keep_x().
  std::size_t dropped_subtrees() const;
  /// The tree in OctoMap's full format (values included), for tests.
  void write(std::ostream& out) const;
  /// True when the voxel containing `p` is occupied.
  bool occupied(const Vec3& p) const;
  /// Frees every occupied voxel whose cube overlaps the robot's shapes (inflated by
  /// `padding_m`) at (base, q): the space the robot fills cannot hold an obstacle, whatever
  /// the camera saw there (leaves brushed aside by the arm, sensor noise). Returns the count.
  std::size_t clear_robot_volume(const RobotModel& model, const BasePose& base, const ArmConfig& q, double padding_m);
  size_t voxel_count() const { return voxel_count_; }
  /// Approximate heap use: the octree's nodes and the coarse grid (`canopy bench mission`).
  std::size_t memory_bytes() const;
  double resolution_m() const { return resolution_m_; }

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  CollisionEnvironment() = default;
  std::unique_ptr<Impl> impl_;
  size_t voxel_count_ = 0;
  double resolution_m_ = 0.0;
};

/// Which robot shapes a query considers against the environment and the ground.
enum class BodySet {
  kAll,      ///< Every shape.
  kArmOnly,  ///< Only shapes moved by the arm joints (the base's were checked once already).
};

/// Every colliding pair found for one state, for diagnostics.
struct CollisionReport {
  bool in_collision = false;
  std::vector<std::string> pairs;  ///< "shape_a | shape_b", "shape | map", "shape | ground".
};

/// Distance from a world point to a robot shape posed at T_world_shape (0 inside): the exact
/// geometry FCL's shapes stand for.
double point_shape_distance(const robot::Shape& shape, const Pose& T_world_shape, const Vec3& p_world);

/// Collision checks for one robot model in one environment. All queries are const and
/// thread-safe (no shared mutable state).
class CollisionChecker {
 public:
  CollisionChecker(const RobotModel& model, const CollisionParams& params,
                   std::shared_ptr<const CollisionEnvironment> environment = nullptr);
  ~CollisionChecker();
  CollisionChecker(CollisionChecker&&) noexcept;

  /// True if the robot at (base, q) touches the map, the ground or itself. Non-finite
  /// input counts as a collision.
  bool in_collision(const BasePose& base, const ArmConfig& q, BodySet set = BodySet::kAll) const;
  /// Only the base-fixed shapes against the map and the ground.
  bool base_in_collision(const BasePose& base) const;
  /// All colliding pairs (slower; for messages and tests).
  CollisionReport report(const BasePose& base, const ArmConfig& q) const;

  /// Self-collision shape pairs that are checked (indices into model().bodies()).
  const std::vector<std::pair<int, int>>& self_pairs() const { return self_pairs_; }
  const RobotModel& model() const { return *model_; }
  const CollisionParams& params() const { return params_; }
  const std::shared_ptr<const CollisionEnvironment>& environment() const { return environment_; }
  /// Another environment (a long row's truth for the plants near the robot, issue 49); not
  /// while another thread queries.
  void set_environment(std::shared_ptr<const CollisionEnvironment> environment) { environment_ = std::move(environment); }

 private:
  struct Shapes;
  bool check(const BasePose& base, const ArmConfig& q, BodySet set, CollisionReport* report) const;

  const RobotModel* model_;
  CollisionParams params_;
  std::shared_ptr<const CollisionEnvironment> environment_;
  std::unique_ptr<Shapes> shapes_;
  std::vector<std::pair<int, int>> self_pairs_;
};

/// Where the arm, held at `q`, first touches the checker's environment or the ground while the
/// base moves in a straight line from `from` to `to` (the yaw of `from` kept): the first base
/// pose, every `step_m` at most, `from` itself not tested and `to` tested, at which it does; or
/// nullopt. Poses whose base x is outside [x_lo_m, x_hi_m] are not tested (a long row's
/// environment held near one stop, CollisionEnvironment::keep_x). A step not > 0 is an
/// InputError.
std::optional<BasePose> held_arm_sweep_hit(const CollisionChecker& checker, const BasePose& from, const BasePose& to,
                                           const ArmConfig& q, double step_m,
                                           double x_lo_m = -std::numeric_limits<double>::infinity(),
                                           double x_hi_m = std::numeric_limits<double>::infinity());

}  // namespace canopy::motion
