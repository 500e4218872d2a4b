#pragma once
// The paper's free-camera ablation (Fig. 5 and 6): one job is a (gain, ray set, P_gt) on one
// plant in one trial. The map starts empty; `initial_views` random views around the plant
// (the same for every configuration of a trial) come first; then every step asks the
// cluster-centric view planner ("ours", with the job's gain and rays) for its views around
// the plant's clusters and takes the best one (a view is never taken twice: the planner's
// TakenViews); when the planner has none, a random fallback view is taken and the reason is
// recorded. After every view the plant's fruit coverage and entropy are recorded, with the
// step's ray-casting time. Deterministic in the seeds; independent of the thread running it.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/mapping/mapping_config.h"
#include "canopy/nbv/nbv_params.h"
#include "canopy/sim/renderer.h"
#include "canopy/world/world.h"

namespace canopy::mission {

/// One configuration of the ablation.
struct AblationConfig {
  std::string gain, rays;
  double pgt = 1.0;
  std::string id() const;  ///< "<gain>_<rays>_pgt<P_gt>", the job folder's name.
};

/// Settings shared by every job.
struct AblationSettings {
  int views = 30;                      ///< Views per plant, initial ones included.
  int initial_views = 2;
  double plant_radius_m = 0.25;        ///< Clusters within this of the plant's axis count.
  double view_radius_m = 0.45;         ///< Random views at this distance from the plant's axis.
  std::uint64_t seed = 1;
};

/// Runs one (configuration, trial, plant) job with a free camera and returns its record
/// (config, trial, plant, seed, fruits, and one entry per view).
nlohmann::json run_ablation_job(const AblationConfig& config, int trial, int plant, const AblationSettings& settings,
                                const mapping::MappingConfig& mapping, const nbv::NbvParams& nbv,
                                const world::World& world, sim::Renderer& renderer);

/// One row of the ablation's table.
struct AblationRow {
  AblationConfig config;
  std::size_t trials = 0;            ///< Trials with every plant done.
  int views_to_target_curve = -1;    ///< First view where the mean coverage curve reaches the target (-1: never).
  double views_to_target_per_plant = 0.0;  ///< Mean over plant runs that reach it.
  std::size_t runs_reaching = 0, runs = 0;
  double raycast_ms_per_view = 0.0;
  double final_coverage = 0.0, final_entropy = 0.0;
};

/// Summarises finished jobs (`results[i]` of `jobs[i]`, null when missing): writes per-trial
/// JSONs under out/trials, out/summary.csv (mean and std per view) and out/table.csv, and
/// returns the table's rows.
struct AblationJobId {
  std::size_t config = 0;
  int trial = 0;
  int plant = 0;
};
std::vector<AblationRow> summarize_ablation(const std::string& out, const std::vector<AblationConfig>& configs,
                                            int plants, int views, const std::vector<nlohmann::json>& results,
                                            const std::vector<AblationJobId>& jobs, double target_coverage);

}  // namespace canopy::mission
