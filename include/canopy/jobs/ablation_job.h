#pragma once
// Job: the free-camera ablation (paper Fig. 5 and 6) into an output folder. What `canopy
// ablate` does once its flags are parsed into a plan: the world loaded and checked (without
// depth noise), the plan run (experiments::run_ablation), the plots drawn, the folder
// published, and a zero coverage explained.

#include <functional>
#include <string>

#include "canopy/experiments/ablation_runner.h"
#include "canopy/settings/settings.h"

namespace canopy::jobs {

/// What run_ablation_job needs.
struct AblationJobParams {
  std::string world_file;                ///< The world (its first plan.plants plants are used).
  experiments::AblationPlan plan;        ///< Configurations, trials, plants, settings (world_name is filled in).
  std::string out;                       ///< Output folder.
  experiments::AblationRunOptions run;   ///< Threads, resume, summarize_only, coverage target, progress, stop.
  bool plots = false;                    ///< Draw gains.svg and rays.svg (figures.h).
  /// Called with the result once the jobs are summarized, before the plots (the CLI's table).
  std::function<void(const experiments::AblationRunResult&)> on_summary;
};

/// What it did.
struct AblationJobResult {
  experiments::AblationRunResult run;
  std::string zero_coverage;  ///< "fruit coverage is 0 in every configuration" and why; "" when it is not.
};

/// Runs the ablation of `params` with the settings `bundle` and publishes the folder. A stop
/// request keeps the finished jobs in the working folder and throws Interrupted (`--resume`
/// continues it); InputError when the world has fewer plants than the plan.
AblationJobResult run_ablation_job(const AblationJobParams& params, const settings::Settings& bundle);

}  // namespace canopy::jobs
