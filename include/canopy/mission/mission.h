#pragma once
// The closed-loop mission (the paper's "Overall performance" experiment) in MuJoCo: for each
// base stop along the aisle the robot drives there, takes the stop's predefined initial scan,
// then asks its view planner (any of nbv::view_planner_registry(): the paper's ours, the
// baselines, canopy's own, the oracles) for
// batches of views until the stop's budget is used up, nothing is left to plan, or a cap is
// hit. Each view: IK -> OMPL plan against the current map (occupied voxels, the ground and
// the robot itself) -> execution on the simulator's servos -> when the camera reached the
// goal, the wrist camera renders from the pose actually reached, and the frame is segmented,
// inserted into the map and evaluated.
//
// The controller is a state machine around library calls: mapping, nbv and motion hold the
// algorithms (and stay MuJoCo-free); this file only sequences them, times them and records
// what happened. Contacts with the true plant geometry are counted (geometrically, against
// the world's voxelised meshes), never used for planning.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "canopy/common/frame.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/records/records.h"
#include "canopy/records/replay.h"
#include "canopy/settings/settings.h"
#include "canopy/motion/arm_planner.h"
#include "canopy/motion/robot_model.h"
#include "canopy/nbv/view_planner.h"
#include "canopy/sim/simulator.h"
#include "canopy/world/world.h"

namespace canopy::mission {

/// Where the planner looks for targets at a stop: the LoopParams box around the arm base's
/// x and the aisle's y (world-aligned).
Eigen::AlignedBox3d stop_region(const settings::LoopParams& loop, double arm_x_m, double base_y_m);

/// The failure cause of a failed arm plan (kNone for success).
records::FailureCause failure_of_plan(motion::PlanStatus status);

/// What the mission gives its planner beside the settings (nbv::ViewPlannerSettings::context):
/// the world and the simulator. The planning library's planners never read it; the oracles
/// (declared in nbv's table, reads_ground_truth) are built from it (oracle/oracle_planners.h),
/// and a planner the mission's caller registers may read it too (one that reads the ground
/// truth must be registered with reads_ground_truth, so that its results say so).
struct MissionContext : nbv::PlannerContext {
  const world::World* world = nullptr;
  sim::Simulator* sim = nullptr;
  std::uint64_t seed = 1;
  evaluation::MetricsParams metrics;  ///< The headline rule of "covered" (the oracle's score).
  settings::OracleParams oracle;
  std::unique_ptr<nbv::ViewPlanner> make_planner(const std::string& name,
                                                 const nbv::ViewPlannerSettings& settings) const override;
};

/// Hooks for the command line (progress, video, Ctrl-C) and for tests (fault injection).
struct MissionCallbacks {
  std::function<void(const std::string& message)> progress;
  /// Called every video_period_s of simulated time with a caption (stop, view, coverage).
  std::function<void(sim::Simulator& sim, const std::string& caption)> video_tick;
  double video_period_s = 0.0;
  /// Polled between steps; true ends the mission early (result marked incomplete).
  std::function<bool()> stop_requested;
  /// Called before every simulation step of a view's move (tests inject faults here).
  std::function<void(sim::Simulator& sim, int attempt)> before_step;
  /// Called after every successful view with its frame, while the simulator is in that state
  /// (before the view's map metrics are known: they are computed beside the next move). It may
  /// read the whole map (Mission::map()): with it set, a long row's map is kept whole (the
  /// index and the collision environment are still held near the robot).
  std::function<void(const records::ViewRecord& view, const LabelledFrame& frame, const sim::Simulator& sim)> on_view;
  /// Records each successful view's map changes, fruit coverage and thumbnails for the report
  /// (replay.h), beside the mission without slowing it; null records nothing.
  records::MapReplay* replay = nullptr;
  /// The half-length [m] of the stretch of x around each stop for which the planner's voxel
  /// index and the arm planner's collision environment hold their voxels (issue 49; both
  /// answer as the whole map's either way, see VoxelIndex::keep_x and
  /// CollisionEnvironment::keep_x). Negative: Mission::kNearRobotM when the simulator renders
  /// the plants per window (a long row), else the whole map; 0: the whole map. For tests.
  double near_robot_m = -1.0;
};

/// Approximate heap bytes of a mission's largest holders beside the world and the simulator
/// (`canopy bench mission`; the kernel's peak is the whole process's).
struct MissionMemory {
  std::size_t map = 0;           ///< The semantic octree (its far part's compact bytes included).
  std::size_t nbv_index = 0;     ///< The next-best-view voxel index (nbv/voxel_index.h).
  std::size_t planning_env = 0;  ///< The arm planner's collision environment (the map's occupied voxels).
  std::size_t truth_env = 0;     ///< The true plants' voxels, for the robot's contacts.
  std::size_t evaluation = 0;    ///< The incremental evaluator (ground-truth points, trees, fruit voxels).
  std::size_t total() const { return map + nbv_index + planning_env + truth_env + evaluation; }
};

/// The mission controller.
class Mission {
 public:
  /// The stretch's half-length on a long row (MissionCallbacks::near_robot_m): the camera's
  /// range and the arm's reach from the stop, with room to spare.
  static constexpr double kNearRobotM = 3.0;
  /// The method is settings.method; `seed` seeds segmentation noise, the planner's draws and OMPL.
  Mission(const world::World& world, const settings::Settings& settings, std::uint64_t seed, MissionCallbacks callbacks = {});
  ~Mission();
  Mission(const Mission&) = delete;
  Mission& operator=(const Mission&) = delete;

  /// Runs every stop; returns what happened (also when interrupted).
  records::MissionResult run();

  // --- Pieces, for tests -----------------------------------------------------------------
  /// Drives to stop k (0-based) and records it; false when the goal was not reached.
  bool drive_to_stop(int k);
  /// Attempts one view at the current stop.
  records::ViewRecord attempt(const nbv::PlannedView& view, records::ViewPhase phase);
  /// The predefined camera poses of stop k in the world (extra: predefined scanning's).
  std::vector<Pose> scan_views(int k, bool extra) const;
  const records::MissionResult& result() const;
  /// The map, whole: on a long row its far part, kept compactly during the mission
  /// (SemanticOcTree::keep_x), is put back first (so memory() then counts it whole). From a
  /// callback while run() runs, the map as held (a read of its far part is an internal error).
  const mapping::SemanticOcTree& map() const;
  /// What its largest holders use now (after run(): at the end).
  MissionMemory memory() const;
  sim::Simulator& simulator();
  const motion::RobotModel& robot() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace canopy::mission
