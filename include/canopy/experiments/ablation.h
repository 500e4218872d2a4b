#pragma once
// The paper's free-camera ablation (Fig. 5 and 6): one job is a (gain, ray set, P_gt) on one
// plant in one trial. The map starts empty. Two protocols, chosen per run:
//  - paper (the released code's; docs/background/released_code.md, the default): ONE initial view from a
//    fixed grid of 10 poses (azimuth 0..90 deg in 5 steps x polar 30 and 120 deg, r = 0.4 m,
//    aimed at 0.5 m above the plant's base; trial i starts from pose i mod 10), then rounds:
//    the cluster-centric planner ("ours", with the job's gain and rays) gives the best view of
//    every unfinished cluster, in tour order from the current camera, and ALL of them are
//    taken before clustering again; a round with no view still counts one view: the camera
//    stays where it is and takes another image (new segmentation noise), so a run whose
//    initial view lost its fruit mask to noise is not stuck for ever.
//  - one_view (canopy's first protocol): `initial_views` random views around the plant, then
//    every step takes only the planner's first view and re-plans; when the planner has none a
//    random fallback view is taken and the reason recorded.
// A view is never taken twice (the planner's TakenViews). After every view the plant's fruit
// coverage and entropy are recorded, with the ray-casting time of the planning step that
// produced it. Deterministic in the seeds; independent of the thread running it.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/common/enum_names.h"
#include "canopy/settings/settings.h"
#include "canopy/sim/renderer.h"
#include "canopy/world/world.h"

namespace canopy::experiments {

/// One configuration of the ablation: the `ours` planner with a gain and a ray set, at one
/// P_gt, with any further settings by key (OSAMCEP's proximity test, or anything a sweep names).
struct AblationConfig {
  std::string gain, rays;
  double pgt = 1.0;
  std::vector<settings::SettingOverride> set;  ///< Applied over the bundle, in order.
  /// The gain, then "-<value>" for OSAMCEP's proximity and "-<leaf key>=<value>" for any other
  /// setting of `set`.
  std::string label() const;
  std::string id() const;     ///< "<label>_<rays>_pgt<P_gt>", the job folder's name.
};

/// The two protocols of the header comment.
enum class AblationProtocol { kPaper, kOneView };
inline constexpr EnumName<AblationProtocol> kAblationProtocolNames[] = {{AblationProtocol::kPaper, "paper"},
                                                                        {AblationProtocol::kOneView, "one_view"}};
/// "paper" / "one_view".
std::string to_string(AblationProtocol p);
/// Parses a protocol name; throws InputError naming `where` otherwise.
AblationProtocol ablation_protocol_from_string(const std::string& s, const std::string& where);

/// Settings shared by every job.
struct AblationSettings {
  AblationProtocol protocol = AblationProtocol::kPaper;
  int views = 30;                      ///< Views per plant, initial ones included.
  int initial_views = 2;               ///< one_view: random initial views (paper: always 1, from the grid).
  double plant_radius_m = 0.25;        ///< Clusters within this of the plant's axis count.
  double view_radius_m = 0.45;         ///< one_view: random views at this distance from the plant's axis.
  double grid_radius_m = 0.4;          ///< paper: initial grid poses at this distance from the aim point.
  double grid_aim_height_m = 0.5;      ///< paper: the grid aims at this height above the plant's base.
  /// When >= 0, replaces the NBV settings' cluster.min_logodds. canopy inserts one hit per
  /// voxel per view (l = psi = 1.0 after one view), the released code one per endpoint (a
  /// single view passes its 1.0), so after ONE initial view nothing clusters at 1.0: the paper
  /// protocol uses 0.5 (one observation) unless told otherwise (see docs/ablation).
  double cluster_min_logodds = -1.0;
  std::uint64_t seed = 1;
};

/// The settings of a configuration's jobs: the bundle with the method (ours, the gain and
/// rays), P_gt, the configuration's settings and the protocol's cluster threshold applied.
settings::Settings ablation_job_settings(const settings::Settings& bundle, const AblationConfig& config,
                                        const AblationSettings& settings);

/// The paper protocol's initial pose of `trial` for a plant whose base is at `base`.
Pose ablation_grid_pose(const Vec3& base, int trial, const AblationSettings& settings);

/// Runs one (configuration, trial, plant) job with a free camera and returns its record
/// (config, trial, plant, seed, fruits, and one entry per view). `bundle` is the run's
/// settings bundle (ablation_job_settings applies the configuration).
nlohmann::json run_ablation_job(const AblationConfig& config, int trial, int plant, const AblationSettings& settings,
                                const settings::Settings& bundle,
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
  long target_points = 0;            ///< Points its views labelled the target class, over every run.
  long true_target_pixels = 0;       ///< Target-class pixels in its frames' true labels, over every run.
  long steps_without_counts = 0;     ///< Steps of job files written before these counts existed.
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

}  // namespace canopy::experiments
