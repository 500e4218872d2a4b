// canopy visibility: Hemming et al.'s fruit-detectability protocol on a world
// (jobs/visibility_job.h, docs/visibility.md).

#include <spdlog/spdlog.h>

#include "canopy/common/interrupt.h"
#include "canopy/jobs/visibility_job.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

void add_visibility_command(CLI::App& app) {
  struct Options {
    std::string world = default_world_path();
    std::string out;
    std::vector<std::uint64_t> seeds;
    double distance = 0.5;
    std::vector<double> section = {0.4, 0.4};
    double max_occlusion = 0.5;
    int points = 300;
    bool no_plot = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "visibility", "Fruit detectability from fixed camera positions per plant section (Hemming et al. 2014)");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->add_option("--seed", opt->seeds, "World seed(s) (repeat or comma-separate; default: the file's); "
                                        "several are also pooled")
      ->delimiter(',');
  sub->add_option("--distance", opt->distance, "Camera to section centre [m]")->capture_default_str();
  sub->add_option("--section", opt->section, "Plant section width (along the row) and height [m]")
      ->expected(2)
      ->capture_default_str();
  sub->add_option("--max-occlusion", opt->max_occlusion, "Detectable: at most this share of the facing surface hidden")
      ->capture_default_str();
  sub->add_option("--points", opt->points, "Ground-truth surface points per fruit (evenly subsampled)")
      ->capture_default_str();
  sub->add_flag("--no-plot", opt->no_plot, "Skip visibility.svg");
  sub->callback([opt] {
    jobs::VisibilityJobParams p;
    p.world_file = opt->world;
    p.seeds = opt->seeds;
    p.out_dir = opt->out;
    p.protocol.distance_m = opt->distance;
    p.protocol.section_width_m = opt->section.at(0);
    p.protocol.section_height_m = opt->section.at(1);
    p.protocol.max_occlusion = opt->max_occlusion;
    p.protocol.points_per_fruit = opt->points;
    p.plot = !opt->no_plot;
    const InterruptScope interrupts;  // Ctrl-C / SIGTERM: nothing is published and nothing left behind
    p.stop_requested = [] { return interrupt_requested(); };
    const jobs::VisibilitySummary s = jobs::run_visibility(p);
    const auto& r = s.results.back();
    spdlog::info("wrote {}/visibility.md, visibility.csv, combinations.csv, fruits.csv, visibility.json: {} fruits, "
                 "best single position {:.0f} %, best five {:.0f} % ({})",
                 opt->out, r.fruits.size(), 100.0 * r.best.front().detectability, 100.0 * r.best.back().detectability,
                 s.labels.back());
  });
}

}  // namespace canopy::cli
