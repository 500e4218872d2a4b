#include "canopy/jobs/ablation_job.h"

#include "canopy/common/error.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/read_file.h"
#include "canopy/jobs/figures.h"
#include "canopy/jobs/world_job.h"
#include "canopy/mission/mission.h"

namespace canopy::jobs {

namespace {

// A zero never goes unexplained.
std::string explain_zero_coverage(const experiments::AblationRunResult& r, const world::World& world,
                                  const settings::Settings& bundle) {
  bool all_zero = !r.rows.empty();
  long target_points = 0, true_pixels = 0, uncounted = 0;
  for (const auto& row : r.rows) {
    all_zero = all_zero && row.final_coverage == 0.0;
    target_points += row.target_points;
    true_pixels += row.true_target_pixels;
    uncounted += row.steps_without_counts;
  }
  if (!all_zero) return "";
  if (uncounted > 0)
    return "fruit coverage is 0 in every configuration; " + std::to_string(uncounted) + " views come from job files of an older canopy that did not count target "
           "pixels: rerun without --resume to learn why";
  return "fruit coverage is 0 in every configuration: " + records::zero_coverage_cause(world.spec.classes.target, bundle.mapping.extractor.source, target_points,
                                      true_pixels);
}

}  // namespace

AblationJobResult run_ablation_job(const AblationJobParams& params, const settings::Settings& bundle) {
  world::WorldSpec spec = load_world_spec(params.world_file);
  spec.camera.depth_noise_k = 0.0;  // segmentation noise only, and renderers stay stateless
  const world::World world = build_world(spec);
  check_world_colours(world, bundle.mapping.extractor);
  experiments::AblationPlan plan = params.plan;
  plan.world_name = spec.name;
  if (plan.plants > int(world.plants.size()))
    throw InputError("--plants: " + std::to_string(plan.plants) + " but the world has " +
                     std::to_string(world.plants.size()));

  // Only resuming (or summarizing) adds to an existing folder; a fresh run replaces it.
  const bool reuse = params.run.resume || params.run.summarize_only;
  StagedDir out(params.out, "ablate", reuse ? StagedDir::Mode::kResume : StagedDir::Mode::kReplace);
  AblationJobResult r;
  r.run = experiments::run_ablation(plan, bundle, world, out, params.run);
  if (r.run.interrupted) {  // the finished jobs stay; --resume continues the folder
    out.keep();
    throw Interrupted("interrupted; the finished jobs are kept in " + out.working_dir() +
                      ", and the same command with --resume continues");
  }
  if (params.on_summary) params.on_summary(r.run);
  if (params.plots) {
    try {
      write_figures(out.working_dir(), ablation_figures(read_file(out.path("summary.csv"))));
    } catch (...) {
      out.keep();  // the finished jobs stay for --resume
      throw;
    }
  }
  out.commit();
  r.zero_coverage = explain_zero_coverage(r.run, world, bundle);
  return r;
}

}  // namespace canopy::jobs
