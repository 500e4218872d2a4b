#pragma once
// candidates.csv, written and read in one place: the candidate audit's records
// (mission/oracle/candidate_audit.h) and the agreement of each score with the truth over
// planning rounds (gain_truth.csv of `canopy report`).

#include <string>
#include <vector>

#include "canopy/evaluation/rank_stats.h"
#include "canopy/nbv/gains.h"
#include "canopy/nbv/nbv_params.h"
#include "canopy/records/records.h"

namespace canopy::records {

/// A score of the candidate audit: a gain of nbv::gain_registry() with the proximity test it
/// is scored with (a gain that reads the proximity test is scored once per test).
struct AuditScore {
  std::string name;  ///< Its column in candidates.csv (osamcep_per_voxel, ..., ae, uvc, ...).
  const nbv::GainEntry* gain = nullptr;
  nbv::Proximity proximity = nbv::Proximity::kPerSegmentEnd;
  bool sets_proximity = false;
};
/// The scores candidates.csv holds beside the truth, in the registry's order.
std::vector<AuditScore> audit_scores();
/// Their names (the columns after `truth`).
std::vector<std::string> audit_score_names();

/// candidates.csv: stop,round,views_before,cluster,x,y,z,qw,qx,qy,qz,chosen,planner_gain,frustum,truth,<scores>.
std::string candidates_csv(const std::vector<CandidateRecord>& records);

/// Agreement of each score with the truth over planning rounds.
struct GainTruthRow {
  std::string score;                  ///< "planner" (the planner's own gain) or a score name.
  evaluation::RankAgreement agreement;
};

/// Reads candidates.csv files by their header's column names and compares the planner's gain
/// and every score of audit_score_names() with the truth, round by round (rounds with fewer
/// than 2 candidates are left out). Throws InputError on a malformed file or a missing column.
std::vector<GainTruthRow> gain_truth(const std::vector<std::string>& candidate_files);
/// The table as CSV: score,rounds,spearman,top1,top5,mean_oracle_rank,truth_share.
std::string gain_truth_csv(const std::vector<GainTruthRow>& rows);

}  // namespace canopy::records
