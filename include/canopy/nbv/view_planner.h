#pragma once
// One interface for the methods that choose the robot's next views, chosen by name from one
// registry (view_planner_registry), and the bookkeeping they share. Each built-in planner has
// its room, nbv/planners/<name>/ (algorithm, parameters, registry entry), listed in one table
// (planners/planners.h): ours, frontier, predefined, global, canopy's own reveal and shape, and
// the two oracles (declared there, built by a context that holds the ground truth). A planner
// from outside this library joins through register_view_planner (one written in Python).
// Planners see only the map, the robot's state and its budget (MuJoCo-free, so the same
// planner could drive a real robot); reachability comes in as callbacks.

#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "canopy/common/timer.h"
#include "canopy/common/params.h"
#include "canopy/nbv/gains.h"
#include "canopy/nbv/view_evaluator.h"
#include "canopy/nbv/ray_sets.h"

namespace canopy::nbv {

/// A view the robot should take, with what the reachability check found.
struct PlannedView {
  Pose T_world_camera = Pose::Identity();  ///< Moved into the workspace when the filter moved it.
  Vec3 target = Vec3::Zero();              ///< The point it looks at.
  int cluster = -1;                        ///< Cluster served (ours), -1 otherwise.
  double gain = 0.0;                       ///< The method's score of the view.
  double shift_m = 0.0;                    ///< Move along the viewing direction by the filter.
  bool has_q = false;                      ///< q: IK solution found by the reachability check.
  ArmConfig q{};
  std::string source;                      ///< Who chose it: "nbv" (ours), "roi", "exploration", "predefined", "global", "reveal", ...
};

/// How the mission executes a batch.
enum class BatchOrder {
  kTour,     ///< Every view, in the order of a tour from the current camera.
  kUtility,  ///< In the given order until one view succeeds.
};

/// What a planner is asked.
struct ViewRequest {
  const mapping::SemanticOcTree* map = nullptr;
  VoxelIndex* index = nullptr;             ///< Kept beside `map`; planners refresh it.
  Pose T_world_camera = Pose::Identity();  ///< The camera now.
  bool has_q = false;                      ///< q holds the arm's joints now.
  ArmConfig q{};
  Eigen::AlignedBox3d region;              ///< Targets (fruit clusters, frontiers) must lie in it.
  int budget = 1;                          ///< Successful views still wanted at this stop.
  std::uint64_t seed = 1;                  ///< Seeds the planner's random draws for this request.
  /// Full reachability check (workspace move + IK), as the paper's filter; may be null.
  CandidateFilter reach;
  /// Position-only reachability (the frontier planner's precomputed workspace); may be null.
  std::function<bool(const Vec3& camera_position)> in_workspace;
  /// The arm planner's goal test at planning time: true when the view, at its own pose (not
  /// moved), has an IK solution at this base that is free of collision as a goal must be. A
  /// view that fails it would fail before any move (no_ik, goal_in_collision); may be null.
  std::function<bool(const PlannedView&)> goal_free;
  /// Scripted views of this stop (predefined scanning), in world coordinates.
  std::vector<Pose> scripted;
  /// When set, planners that score candidates call it with every candidate they scored
  /// (after the reach test), in scoring order; it never changes their choice.
  CandidateObserver on_scored;
};

/// A planner's answer.
struct ViewBatch {
  std::vector<PlannedView> views;          ///< Best first.
  BatchOrder order = BatchOrder::kTour;
  bool finished = false;                   ///< Nothing left to plan at this stop (no positive gain).
  std::string reason;                      ///< Why `views` is empty.
  std::size_t clusters = 0;                ///< Clusters (ours) or targets (frontier) considered.
  std::size_t candidates = 0;              ///< Candidates scored.
  std::size_t filtered = 0;                ///< Candidates dropped by reachability.
  bool last_of_stop = false;               ///< The stop ends once this batch is executed (`reason` says why).
  /// Scripted views the planner refused before any move (they fail ViewRequest::goal_free):
  /// not attempts; the mission hands them to replace_failed (PlannerTraits::replaces_failed).
  std::vector<PlannedView> refused;
  PhaseTimes times;                        ///< clustering, candidates, filtering, scoring.
};

/// What the mission controller must know about a planner; it never tests a planner's name.
struct PlannerTraits {
  /// Takes the stop's scripted views (ViewRequest::scripted): a scan, not a choice; its views
  /// are recorded in the "predefined" phase.
  bool scripted = false;
  /// Every view of a kTour batch is attempted, even past the stop's budget of successful views.
  bool execute_whole_batch = false;
  /// A scripted view (the initial scan's or ViewRequest::scripted) that fails is handed to
  /// replace_failed (when the mission's scan settings allow replacements).
  bool replaces_failed = false;
};

/// True when two camera poses are the same view (within 1 mm and 0.1 deg).
bool same_view(const Pose& a, const Pose& b);

/// A scripted view the robot could not take, what the controller offers in its place and how
/// it attempts a view (ViewPlanner::replace_failed).
struct FailedScriptedView {
  PlannedView failed;                ///< The view that failed.
  std::vector<PlannedView> options;  ///< Views of the stop's scan pattern around it, nearest first.
  std::vector<Pose> scripted;        ///< The stop's whole scan pattern (initial and extra views).
  int max_attempts = 0;              ///< Replacements attempted at most.
  const int* attempts_left = nullptr;  ///< The stop's attempt budget, when it has one (attempt() spends it).
  /// True when the view passes the arm planner's goal test at this base (an IK solution free
  /// of collision as a goal must be): it would not fail before the arm moves.
  std::function<bool(const PlannedView&)> reachable;
  /// Executes the view and records it; true when it succeeded.
  std::function<bool(const PlannedView&)> attempt;
};

/// Views already taken: a candidate within the tolerances of one of them is never taken again.
class TakenViews {
 public:
  explicit TakenViews(const ViewRules& rules = ViewRules{}) : rules_(rules) {}
  void add(const Pose& T_world_camera) { poses_.push_back(T_world_camera); }
  /// True when `T_world_camera` lies within taken_position_m and taken_angle_deg of a taken view.
  bool contains(const Pose& T_world_camera) const;
  std::size_t size() const { return poses_.size(); }

 private:
  ViewRules rules_;
  std::vector<Pose> poses_;
};

/// Clusters found done: a later cluster whose centroid lies within done_epsilon_m of a done
/// one stays done (centroids move a little when clusters are recomputed).
class DoneClusters {
 public:
  explicit DoneClusters(const ViewRules& rules = ViewRules{}) : rules_(rules) {}
  void mark(const Vec3& centroid) { done_.push_back(centroid); }
  bool contains(const Vec3& centroid) const;
  std::size_t size() const { return done_.size(); }
  void clear() { done_.clear(); }

 private:
  ViewRules rules_;
  std::vector<Vec3> done_;
};

/// What became of one attempted view (ViewPlanner::outcome): every attempt the mission makes
/// at a stop is reported, successes and failures, the initial scan's included.
struct ViewOutcome {
  PlannedView view;               ///< The view as attempted (pose, target, source, gain, ...).
  bool success = false;
  /// Why it failed ("" on success): no_ik, start_in_collision, goal_in_collision, plan_timeout,
  /// invalid_input, not_reached, unstable (the mission's failure causes, docs/mission.md).
  std::string failure;
  std::string detail;             ///< One line: the failure's detail, or what was done.
  Pose T_reached = Pose::Identity();  ///< The camera pose the frame was taken from (success).
  int stop = 0;                   ///< Base stop (0-based).
  int attempt = 0;                ///< Attempt number over the mission (0-based).
  std::string phase;              ///< "initial", "nbv" or "predefined".
  bool start_repaired = false;    ///< The arm's start was in collision and was repaired first.
};

/// The failed-view rule: true when `outcome` puts its view among a planner's failed_views(): it
/// failed for a cause of its own (no IK, goal in collision, no path, not reached), not for a
/// start in collision or an unstable simulation, which say nothing about the view. The Python
/// planner's request.failed_views applies the same rule.
bool joins_failed_views(const ViewOutcome& outcome);

/// A method that picks views. Stateful (taken views, done clusters), one per mission.
class ViewPlanner {
 public:
  virtual ~ViewPlanner() = default;
  /// Registry name.
  virtual std::string name() const = 0;
  /// What the controller must know about this planner.
  virtual PlannerTraits traits() const { return {}; }
  /// The next batch of views for `request`.
  virtual ViewBatch next(const ViewRequest& request) = 0;
  /// Told after each view the robot took (reached and observed), so it is not taken again.
  virtual void taken(const Pose& T_world_camera) { taken_.add(T_world_camera); }
  /// Told after every attempted view, successful or not, with why it failed (after taken()
  /// for a success). Default: nothing (planners that want to avoid failing views override it).
  /// Default: a view that failed for a cause of its own (not a start in collision or an
  /// unstable simulation) joins failed_views(). Overrides call it too.
  virtual void outcome(const ViewOutcome& outcome);
  /// A new base stop begins.
  virtual void begin_stop() {}
  /// Replaces a scripted view that failed by attempting others through `request.attempt`
  /// (PlannerTraits::replaces_failed); true when one succeeded. Default: no replacement.
  virtual bool replace_failed(const FailedScriptedView& /*request*/) { return false; }
  const TakenViews& taken_views() const { return taken_; }
  /// Views attempted and failed for a cause of their own (no IK, goal in collision, no path,
  /// not reached), over the mission: a planner may keep them out of its next batches.
  const TakenViews& failed_views() const { return failed_views_; }

 protected:
  explicit ViewPlanner(const ViewRules& rules) : taken_(rules), failed_views_(rules) {}
  /// True when `candidate` may be offered: neither taken nor in `failed`, reachable when the
  /// request can tell, and still neither taken nor failed after that test, which may move it.
  template <class Failed>
  bool offerable(Candidate* candidate, const ViewRequest& request, const Failed& failed) const {
    auto fresh = [&] {
      return !taken_.contains(candidate->T_world_camera) && !failed.contains(candidate->T_world_camera);
    };
    return fresh() && (!request.reach || request.reach(candidate)) && fresh();
  }
  TakenViews taken_;
  TakenViews failed_views_;
};

/// Which method picks the views: a view planner by name, with the gain and ray set its
/// scoring uses (`ours`; the others ignore them). The settings bundle's `method` section.
struct MethodChoice {
  std::string name = "ours";
  std::string gain = "osamcep";
  std::string rays = "ours";

  template <class A>
  void visit(A& a);
  bool operator==(const MethodChoice& o) const { return name == o.name && gain == o.gain && rays == o.rays; }
};

struct ViewPlannerSettings;

/// What a caller may hand a planner beyond its settings, in a type this library does not
/// know: the mission passes its world and simulator (mission::MissionContext). Planners of
/// this library never look at it. The oracles (builtin_view_planners' entries that read the
/// ground truth) are declared here but built by the context: only a simulated mission, which
/// holds the truth, can make them.
struct PlannerContext {
  virtual ~PlannerContext() = default;
  /// The planner `name` that only this context can build (an oracle), or nullptr.
  virtual std::unique_ptr<ViewPlanner> make_planner(const std::string& name, const ViewPlannerSettings& settings) const;
};

/// What a planner is built from.
struct ViewPlannerSettings {
  NbvParams params;
  CameraIntrinsics intrinsics;
  MethodChoice method;
  std::shared_ptr<const PlannerContext> context;  ///< May be null (no mission: canopy nbv, tests).
};

/// One registry entry.
struct ViewPlannerEntry {
  std::string name;         ///< [a-z0-9_-]+, unique.
  std::string description;  ///< One line.
  std::function<std::unique_ptr<ViewPlanner>(const ViewPlannerSettings&)> make;
  bool reads_ground_truth = false;  ///< An oracle: reported as such wherever its results go.
  /// Its own parameters, the section nbv.<name> of the settings (planner_section<P>(help)):
  /// read for the built-in planners (builtin_planner_sections); empty: none.
  PlannerSection params = {};
};

/// A PlannedView of a scored candidate (what the filter moved, the IK it found).
PlannedView planned_view(const Candidate& candidate, double gain, const std::string& source);

/// Ends a scoring planner's round: `scored` sorted by gain (stable, best first), the first
/// `max_views` with a gain > 0 become batch->views tagged `source` (each passed to `offered`),
/// batch->candidates counts them all, and an empty batch is finished with the reason "every
/// candidate was filtered out" (nothing scored) or `nothing_reason`.
void take_best_views(std::vector<ScoredView> scored, int max_views, const std::string& source,
                     const std::string& nothing_reason, const std::function<void(const Pose&)>& offered,
                     ViewBatch* batch);

/// The registry: the built-in planners (builtin_view_planners), then the registered planners in the order they
/// were registered.
std::vector<ViewPlannerEntry> view_planner_registry();
/// Adds a planner under a new name, from outside this library (another module of canopy, or
/// another project linking the installed package). Throws InputError when the name is taken
/// or not made of [a-z0-9_-]. Thread-safe; register before settings naming it are loaded.
void register_view_planner(ViewPlannerEntry entry);
/// The registry entry called `name`, or nullptr.
const ViewPlannerEntry* find_view_planner(const std::string& name);
/// Names of the registry, in order.
std::vector<std::string> view_planner_names();
/// The planner settings.method names; throws InputError naming `where` and the valid names
/// otherwise (or for an unknown gain or ray set).
std::unique_ptr<ViewPlanner> make_view_planner(const ViewPlannerSettings& settings, const std::string& where = "method");

template <class A>
void MethodChoice::visit(A& a) {
  a.one_of("name", name, view_planner_names(), "View planner");
  a.one_of("gain", gain, gain_names(), "Information gain (ours)");
  a.one_of("rays", rays, ray_set_names(), "Ray set (ours)");
}

}  // namespace canopy::nbv
