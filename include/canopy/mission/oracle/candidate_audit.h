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
#include "canopy/records/records.h"
#include "canopy/settings/settings.h"
#include "canopy/nbv/view_features.h"
#include "canopy/nbv/view_planner.h"
#include "canopy/sim/simulator.h"
#include "canopy/world/world.h"

namespace canopy::mission {

/// Scores every candidate a planner scored (ViewRequest::on_scored) by every gain and by the
/// truth, one planning round at a time. READS THE GROUND TRUTH.
class CandidateAudit {
 public:
  CandidateAudit(const world::World& world, sim::Simulator& sim, const settings::Settings& settings);
  /// The observer to pass to the planner for the coming round.
  nbv::CandidateObserver observer();
  /// Scores the round's candidates against `index` (the map as the planner saw it) and the truth.
  /// Each candidate also gets its view features (nbv/view_features.h) for the stop `region`
  /// and the camera at T_world_camera.
  void end_round(const mapping::SemanticOcTree& map, const nbv::VoxelIndex& index, const nbv::ViewBatch& batch,
                 int stop, int round, int views_before, std::uint64_t seed, const Eigen::AlignedBox3d& region,
                 const Pose& T_world_camera);
  /// The records of every round so far.
  const std::vector<records::CandidateRecord>& records() const { return records_; }

 private:
  const world::World& world_;
  settings::Settings settings_;
  std::unique_ptr<evaluation::TruthViewScorer> scorer_;
  int scorer_stop_ = -1;  // the stop whose truth renders the scorer keeps
  std::vector<std::unique_ptr<nbv::GainFunction>> gains_;
  nbv::ViewFeatures features_;
  std::vector<nbv::ScoredView> pending_;
  std::vector<records::CandidateRecord> records_;
};

}  // namespace canopy::mission
