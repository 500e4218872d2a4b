#pragma once
// The oracle planners: views scored by the GROUND TRUTH (evaluation/truth_score.h). They read
// the world (the true fruit surfaces) and render the true scene, so they are no planners a real
// robot could run; they bound what a planner can reach (docs/experiments/). They live in the
// mission, which holds the world and the simulator, and join the nbv registry from outside
// (register_oracle_planners), as a planner written in Python does:
//  - oracle: ours' clusters, candidates, workspace filter and reach test (nbv::ours'
//    selection, the same functions ours runs), and the taken-view rule, each candidate scored
//    by the truth; greedy: the best views of the round, tried in order until one succeeds. It
//    bounds what any gain can do with ours' candidates.
//  - oracle_any: a dense set of views around every target fruit of the stop with uncovered
//    points (OracleParams::any_*), the workspace and reach test; it bounds what the candidate
//    generator can do.

#include <memory>

#include "canopy/common/camera.h"
#include "canopy/evaluation/truth_score.h"
#include "canopy/mission/mission_params.h"
#include "canopy/sim/simulator.h"

namespace canopy::mission {

/// A truth scorer that renders `sim`'s scene (robot hidden, no depth noise) at `camera`
/// divided by params.render_downsample, with params.depth_tolerance_m.
std::unique_ptr<evaluation::TruthViewScorer> make_truth_scorer(sim::Simulator& sim, const CameraIntrinsics& camera,
                                                               const OracleParams& params);

/// Registers oracle and oracle_any in the view-planner registry (once; thread-safe), marked
/// reads_ground_truth. They need the mission's context (MissionContext): anywhere else they
/// throw InputError.
void register_oracle_planners();

}  // namespace canopy::mission
