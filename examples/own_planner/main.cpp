// own_planner [WORLD_FILE [OUT_DIR]]: a view planner written outside canopy's tree, registered
// under its own name and run in canopy's full closed-loop mission (driving, IK and motion
// planning, rendering, mapping and metrics stay canopy's). The planner, "nearest", takes for
// each fruit cluster in the stop's region the reachable candidate view nearest the camera.
// Prints the fruit surface coverage after each successful view; with OUT_DIR also writes the
// run folder `canopy mission` writes. canopy's data (robot, configs, worlds) comes from
// CANOPY_DATA_DIR or the install prefix.

#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <string>

#include "canopy/common/error.h"
#include "canopy/common/output_dir.h"
#include "canopy/mission/mission.h"
#include "canopy/records/run_folder.h"
#include "canopy/nbv/candidates.h"
#include "canopy/nbv/clusters.h"
#include "canopy/nbv/view_planner.h"

namespace {

using namespace canopy;

// What a planner gets: the request (the map and its voxel index, the camera now, the stop's
// region, the budget, a seed, the reachability test) and, by taken(), each view the robot
// took. What it returns: a batch of views, best first, and how the controller runs it.
class NearestPlanner : public nbv::ViewPlanner {
 public:
  explicit NearestPlanner(const nbv::ViewPlannerSettings& settings)
      : ViewPlanner(settings.params.views), params_(settings.params) {}

  std::string name() const override { return "nearest"; }

  nbv::ViewBatch next(const nbv::ViewRequest& request) override {
    nbv::ViewBatch batch;
    batch.order = nbv::BatchOrder::kTour;  // every view, in the order of a tour
    const std::vector<nbv::Cluster> clusters = nbv::find_clusters(*request.map, params_.cluster, &request.region);
    batch.clusters = clusters.size();
    const Vec3 camera = request.T_world_camera.translation();
    for (std::size_t i = 0; i < clusters.size(); ++i) {
      nbv::Candidate best;
      double best_m = std::numeric_limits<double>::infinity();
      for (nbv::Candidate c : nbv::sample_candidates(clusters[i].centroid, static_cast<int>(i), params_.candidates)) {
        ++batch.candidates;
        // The reachability test may move the view into the workspace; a taken view is never retaken.
        if (taken_.contains(c.T_world_camera) || (request.reach && !request.reach(&c)) ||
            taken_.contains(c.T_world_camera)) {
          ++batch.filtered;
          continue;
        }
        const double m = (c.T_world_camera.translation() - camera).norm();
        if (m < best_m) {
          best_m = m;
          best = c;
        }
      }
      if (best_m < std::numeric_limits<double>::infinity())
        batch.views.push_back(nbv::planned_view(best, /*gain=*/-best_m, "nbv"));
    }
    batch.finished = batch.views.empty();  // ends the stop
    if (batch.finished) batch.reason = clusters.empty() ? "no fruit clusters in reach" : "no reachable view left";
    return batch;
  }

 private:
  nbv::NbvParams params_;
};

}  // namespace

int main(int argc, char** argv) {
  using namespace canopy;
  if (argc > 3) {
    std::fprintf(stderr, "usage: %s [WORLD_FILE [OUT_DIR]]\n", argv[0]);
    return 2;
  }
  try {
    // Register before any settings name the planner.
    nbv::register_view_planner({"nearest", "for each fruit cluster, the reachable candidate view nearest the camera",
                                [](const nbv::ViewPlannerSettings& s) { return std::make_unique<NearestPlanner>(s); }});

    const RobotConfig robot = default_robot_config();
    settings::Settings settings = settings::Settings::load(find_data_file(settings::default_settings_path()), robot);
    settings.set("method.name", "nearest", "own_planner");
    settings.set("mission.loop.views_per_stop", "2", "own_planner");
    const std::string world_file = argc > 1 ? argv[1] : "worlds/small.yaml";
    const world::World world = world::generate_world(world::WorldSpec::load(find_data_file(world_file)));

    mission::Mission mission(world, settings, /*seed=*/1);
    const records::MissionResult result = mission.run();
    for (const records::ViewRecord& v : result.views)
      if (v.success) std::printf("view %d (%s): fruit SC %.3f\n", v.successful_views, v.source.c_str(), v.coverage);
    std::printf("planner '%s': %d of %zu views successful, fruit SC %.3f, %.1f s simulated\n",
                settings.method.name.c_str(), result.successful_views(), result.views.size(),
                result.final_metrics.coverage, result.sim_time_s);
    if (argc > 2) {
      StagedDir out(argv[2], "mission");
      records::RunContext context;
      context.world_file = world_file;
      context.world = &world;
      records::write_run_folder(out.working_dir(), result, settings, mission.map(), context);
      out.commit();
      std::printf("wrote %s\n", argv[2]);
    }
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
