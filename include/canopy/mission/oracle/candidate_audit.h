#pragma once
// The candidate audit (mission.record.candidates): every candidate a planner scored in a
// planning round, scored again by every gain of the registry and by the truth. READS THE
// GROUND TRUTH. Its records go to candidates.csv (mission/oracle/candidates_csv.h).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "canopy/evaluation/truth_score.h"
#include "canopy/mission/settings.h"
#include "canopy/nbv/view_planner.h"
#include "canopy/sim/simulator.h"
#include "canopy/world/world.h"

namespace canopy::mission {

/// The scores candidates.csv holds beside the truth: every gain of nbv::gain_registry() in
/// its order, a gain that reads the proximity test once per test (osamcep_per_voxel,
/// osamcep_per_segment_end, ae, uvc, uvpc, oae, mi, rs).
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
/// truth, one planning round at a time. READS THE GROUND TRUTH.
class CandidateAudit {
 public:
  CandidateAudit(const world::World& world, sim::Simulator& sim, const Settings& settings);
  /// The observer to pass to the planner for the coming round.
  nbv::CandidateObserver observer();
  /// Scores the round's candidates against `index` (the map as the planner saw it) and the truth.
  void end_round(const mapping::SemanticOcTree& map, const nbv::VoxelIndex& index, const nbv::ViewBatch& batch,
                 int stop, int round, int views_before, std::uint64_t seed);
  /// The records of every round so far.
  const std::vector<CandidateRecord>& records() const { return records_; }

 private:
  const world::World& world_;
  Settings settings_;
  std::unique_ptr<evaluation::TruthViewScorer> scorer_;
  int scorer_stop_ = -1;  // the stop whose truth renders the scorer keeps
  std::vector<std::unique_ptr<nbv::GainFunction>> gains_;
  std::vector<nbv::ScoredView> pending_;
  std::vector<CandidateRecord> records_;
};

}  // namespace canopy::mission
