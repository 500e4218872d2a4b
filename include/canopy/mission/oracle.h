#pragma once
// The oracle: views scored by the GROUND TRUTH. It reads the world (the true fruit surfaces)
// and renders the true scene, so it is no planner a real robot could run; it bounds what a
// planner can reach and measures how well the planners' gains rank views (docs/experiments/).
//
// A view's truth score is the number of target-fruit surface points not yet covered under the
// headline evaluation rule (evaluation::uncovered_target_points) that it would see: points in
// the camera's valid depth range whose depth passes a test against a depth render of the true
// scene (robot hidden) from the view's pose. The render may be coarser than the camera's
// (OracleParams::render_downsample); a test shows the coarse one agrees with the full one.
//
// Two view planners are registered under names that say so (register_oracle_planners):
//  - oracle: ours' clusters, candidates, workspace filter and reach test, and the taken-view
//    rule, each candidate scored by the truth; greedy: the best views of the round, tried in
//    order until one succeeds. It bounds what any gain can do with ours' candidates.
//  - oracle_any: a dense set of views around every target fruit of the stop with uncovered
//    points (OracleParams::any_*), the workspace and reach test; it bounds what the candidate
//    generator can do.

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "canopy/evaluation/map_metrics.h"
#include "canopy/evaluation/rank_stats.h"
#include "canopy/mission/settings.h"
#include "canopy/nbv/planner.h"
#include "canopy/nbv/voxel_index.h"
#include "canopy/world/world.h"
#include "canopy/sim/renderer.h"
#include "canopy/sim/simulator.h"

namespace canopy::mission {

/// Counts the given truth points a camera pose sees (READS THE GROUND TRUTH through the
/// points it is given and the render of the true scene).
class TruthViewScorer {
 public:
  /// Renders `sim`'s scene with `camera` divided by `downsample` on each side (no depth noise).
  TruthViewScorer(sim::Simulator& sim, const CameraIntrinsics& camera, int downsample, double depth_tolerance_m);

  /// The points still to be seen (e.g. uncovered_target_points of the current map).
  void set_points(std::vector<evaluation::UncoveredPoint> points);
  const std::vector<evaluation::UncoveredPoint>& points() const { return points_; }

  /// Points inside the view's frustum and valid depth range (no occlusion): an upper bound of
  /// visible(), without rendering.
  std::size_t in_frustum(const Pose& T_world_camera) const;
  /// Points the view sees: in the frustum and not behind the rendered true surface.
  std::size_t visible(const Pose& T_world_camera);

  const CameraIntrinsics& render_intrinsics() const { return intrinsics_; }
  std::size_t renders() const { return renders_; }

 private:
  CameraIntrinsics camera_, intrinsics_;
  double tolerance_m_;
  sim::Renderer renderer_;
  std::vector<evaluation::UncoveredPoint> points_;
  std::size_t renders_ = 0;
};

/// A view scored by the truth.
struct TruthScore {
  std::size_t view = 0;    ///< Index into the views given.
  std::size_t bound = 0;   ///< Uncovered points in its frustum.
  std::size_t score = 0;   ///< Uncovered points it sees.
};

/// The `keep` views of `views` that see the most uncovered points (score > 0), best first
/// (ties: the earlier view), by branch and bound: views are rendered in the order of their
/// frustum bound until the bound cannot beat the keep-th best score, so the answer equals
/// rendering every view. `accept(i, &pose)`, when given, is asked just before view i is
/// rendered; it may move the pose (a reach test) or refuse the view.
std::vector<TruthScore> best_truth_views(TruthViewScorer& scorer, std::vector<Pose>* views, std::size_t keep,
                                         const std::function<bool(std::size_t, Pose*)>& accept = nullptr);

/// The scores candidates.csv holds beside the truth: OSAMCEP with both proximity tests
/// (osamcep_per_voxel, osamcep_per_segment_end), ae, uvc, uvpc, oae, mi, rs.
std::vector<std::string> audit_score_names();

/// One candidate of one planning round, scored by every gain and by the truth.
struct CandidateRecord {
  int stop = 0;
  int round = 0;               ///< Planning round of the stop (0-based).
  int views_before = 0;        ///< Successful views of the mission before the round.
  int cluster = -1;
  Pose T_world_camera = Pose::Identity();
  bool chosen = false;         ///< The planner's best view of the round.
  double planner_gain = 0.0;   ///< The planner's own score.
  std::size_t frustum = 0;     ///< Uncovered truth points in its frustum.
  std::size_t truth = 0;       ///< Uncovered truth points it sees (the oracle's score).
  std::vector<double> scores;  ///< audit_score_names() order.
};

/// Scores every candidate a planner scored (ViewRequest::on_scored) by every gain and by the
/// truth, one planning round at a time (mission.record.candidates). READS THE GROUND TRUTH.
class CandidateAudit {
 public:
  CandidateAudit(const world::World& world, sim::Simulator& sim, const Settings& settings);
  /// The observer to pass to the planner for the coming round.
  nbv::CandidateObserver observer();
  /// Scores the round's candidates against `index` (the map as the planner saw it) and the truth.
  void end_round(const mapping::SemanticOcTree& map, const nbv::VoxelIndex& index, const nbv::ViewBatch& batch,
                 int stop, int round, int views_before, std::uint64_t seed);
  const std::vector<CandidateRecord>& records() const { return records_; }

 private:
  const world::World& world_;
  Settings settings_;
  TruthViewScorer scorer_;
  std::vector<std::unique_ptr<nbv::GainFunction>> gains_;
  std::vector<nbv::ScoredView> pending_;
  std::vector<CandidateRecord> records_;
};

/// candidates.csv: stop,round,views_before,cluster,x,y,z,qw,qx,qy,qz,chosen,planner_gain,frustum,truth,<scores>.
std::string candidates_csv(const std::vector<CandidateRecord>& records);

/// Agreement of each score with the truth over planning rounds.
struct GainTruthRow {
  std::string score;                  ///< A score name, or "chosen" (the planner's actual choices).
  evaluation::RankAgreement agreement;
};

/// Reads candidates.csv files and compares every score with the truth, round by round
/// (rounds with fewer than 2 candidates are left out). Throws InputError on a malformed file.
std::vector<GainTruthRow> gain_truth(const std::vector<std::string>& candidate_files);
/// The table as CSV: score,rounds,spearman,top1,top5,mean_oracle_rank,truth_share.
std::string gain_truth_csv(const std::vector<GainTruthRow>& rows);

/// Registers oracle and oracle_any in the view-planner registry (once; thread-safe), marked
/// reads_ground_truth. They need the mission's context (MissionContext): anywhere else they
/// throw InputError.
void register_oracle_planners();

}  // namespace canopy::mission
