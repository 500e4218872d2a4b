#pragma once
// The oracle planners: views scored by the GROUND TRUTH (evaluation/truth_score.h). They read
// the world (the true fruit surfaces) and render the true scene, so they are no planners a real
// robot could run; they bound what a planner can reach (docs/experiments/). They live in the
// mission, which holds the world and the simulator: nbv's table of built-in planners declares
// them (reads_ground_truth), and the mission's context builds them (MissionContext):
//  - oracle: ours' clusters, candidates, workspace filter and reach test (nbv::ours'
//    selection, the same functions ours runs), and the taken-view rule, each candidate scored
//    by the truth; greedy: the best views of the round, tried in order until one succeeds. It
//    bounds what any gain can do with ours' candidates. With OracleParams::candidates
//    "learned" it scores learned's candidates instead (spheres around the shape fit's fruit
//    centres): what a perfect ranker could do with learned's candidate set.
//  - oracle_any: a dense set of views around every target fruit of the stop with uncovered
//    points (OracleParams::any_*), the workspace and reach test; it bounds what the candidate
//    generator can do.

#include <memory>

#include "canopy/common/camera.h"
#include "canopy/evaluation/truth_score.h"
#include "canopy/nbv/view_planner.h"
#include "canopy/settings/mission_params.h"
#include "canopy/sim/simulator.h"

namespace canopy::mission {

/// A truth scorer that renders `sim`'s scene (robot hidden, no depth noise) at `camera`
/// divided by params.render_downsample, with params.depth_tolerance_m.
std::unique_ptr<evaluation::TruthViewScorer> make_truth_scorer(sim::Simulator& sim, const CameraIntrinsics& camera,
                                                               const settings::OracleParams& params);

struct MissionContext;

/// The oracle planner `name` ("oracle" or "oracle_any") over `context`'s world and simulator;
/// nullptr for another name.
std::unique_ptr<nbv::ViewPlanner> make_oracle_planner(const std::string& name, const nbv::ViewPlannerSettings& settings,
                                                      const MissionContext& context);

}  // namespace canopy::mission
