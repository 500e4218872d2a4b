// canopy mission / canopy run: the closed-loop mission on the moving robot (mission::Mission),
// and the files it leaves: views.csv, timing.csv, summary.json, settings.yaml, the final map
// (map.csm, map.ply, map.bt), sc_entropy.svg and runtime.svg, report.html, and optionally a video.
// `canopy run` is the default mission (method ours) writing to results/.

#include <spdlog/spdlog.h>

#include "canopy/common/error.h"
#include "canopy/common/interrupt.h"
#include "canopy/common/value_text.h"
#include "canopy/jobs/mission_job.h"
#include "canopy/jobs/world_job.h"
#include "canopy/video/video.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {

struct MissionCliOptions {
  std::string world = default_world_path();
  std::string config = settings::default_settings_path();
  std::string method = "ours", gain = "osamcep", rays = "ours";  // override the bundle's `method` when given
  std::vector<std::string> set;
  std::string seg, stops, out, video, video_size = "640x480", export_dir;
  std::string mcap, mcap_compression = "zstd", mcap_depth = "32FC1", mcap_epoch = "run";
  double pgt = -1.0;  // < 0: the config's
  int views_per_stop = -1;
  std::uint64_t seed = 1;
  double video_fps = 25.0;
  bool no_plots = false;
  bool no_report = false;
  bool strict = false;
};

void add_options(CLI::App* sub, MissionCliOptions* o, bool out_required) {
  sub->add_option("--world", o->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--config", o->config, kConfigHelp)->capture_default_str();
  sub->add_option("--method", o->method, "View planner: " + [] {
        std::string s;
        for (const auto& e : nbv::view_planner_registry())
          s += (s.empty() ? "" : ", ") + e.name + (e.reads_ground_truth ? " (ORACLE: reads the ground truth)" : "");
        return s;
      }() + " (default: the bundle's method.name, ours)");
  sub->add_option("--gain", o->gain, "Information gain of method ours (default: the bundle's method.gain, osamcep)");
  sub->add_option("--rays", o->rays, "Ray set of method ours: ours, dense, sparse (default: the bundle's method.rays)");
  sub->add_option("--set", o->set, "Any setting of the bundle, KEY=VALUE (e.g. nbv.gain.proximity=per_voxel); repeatable");
  sub->add_option("--pgt", o->pgt, "Segmentation noise P_gt (1 = none; default: the config's)");
  sub->add_option("--seg", o->seg, "Labels: color or truth (default: the config's)")
      ->check(CLI::IsMember({"color", "truth"}));
  sub->add_option("--seed", o->seed, "Seed of segmentation noise, planners and OMPL")->capture_default_str();
  sub->add_option("--stops", o->stops, "Base stops: a count N (evenly spaced) or arm-base x positions x1,x2,...");
  sub->add_option("--views-per-stop", o->views_per_stop, "Successful NBV views wanted per stop (default: the config's)");
  auto* out = sub->add_option("--out", o->out, "Output folder");
  if (out_required) out->required();
  else out->capture_default_str();
  sub->add_option("--video", o->video, "Also record an H.264 MP4 of the run (chase view, wrist and map insets, caption)");
  sub->add_option("--video-size", o->video_size, "Video frame size WxH")->capture_default_str();
  sub->add_option("--video-fps", o->video_fps, "Video frames per simulated second")->capture_default_str();
  sub->add_flag("--no-plots", o->no_plots, "Skip sc_entropy.svg and runtime.svg");
  sub->add_flag("--no-report", o->no_report, "Skip report.html (the interactive 3D report, docs/report.md)");
  sub->add_flag("--strict", o->strict, kStrictColoursHelp);
  sub->add_option("--export", o->export_dir,
                  "Also write a NeRF / Gaussian-splatting dataset (nerfstudio layout) of every successful view, "
                  "with held-out ring views, into this folder");
  sub->add_option("--mcap", o->mcap, "Also record the run as a ROS 2 MCAP file while it runs (docs/ros2.md)");
  sub->add_option("--mcap-compression", o->mcap_compression, "--mcap chunks: none, lz4 or zstd")->capture_default_str();
  sub->add_option("--mcap-depth", o->mcap_depth, "--mcap depth: 32FC1 (m, NaN = no return) or 16UC1 (mm, 0)")
      ->capture_default_str();
  sub->add_option("--mcap-epoch", o->mcap_epoch,
                  "--mcap stamps: epoch + simulated time; epoch 'run' (the run's start, wall clock), 'zero' or "
                  "seconds since 1970")
      ->capture_default_str();
}

void run_mission(const MissionCliOptions& o, CLI::App* sub) {
  // Ctrl-C and SIGTERM from here on: the views so far are saved, marked incomplete.
  const InterruptScope interrupts;
  // Validate every input before any work.
  if (!o.video.empty()) video::VideoWriter::validate_output_path(o.video);
  jobs::MissionJobParams job;
  if (!o.mcap.empty()) job.mcap = jobs::mcap_record_options(o.mcap, o.mcap_compression, o.mcap_depth, o.mcap_epoch);
  const world::WorldSpec spec = jobs::load_world_spec(o.world);
  job.settings = load_settings(o.config);
  settings::Settings& settings = job.settings;
  if (sub->count("--method")) settings.set("method.name", o.method, "--method");
  if (sub->count("--gain")) settings.set("method.gain", o.gain, "--gain");
  if (sub->count("--rays")) settings.set("method.rays", o.rays, "--rays");
  // Flags set settings by their keys: the same limits as in a settings file.
  if (sub->count("--pgt")) settings.set("mapping.extractor.p_gt", format_number(o.pgt, NumberFormat::kDigits17), "--pgt");
  if (!o.seg.empty()) settings.set("mapping.extractor.source", o.seg, "--seg");
  if (sub->count("--views-per-stop"))
    settings.set("mission.loop.views_per_stop", std::to_string(o.views_per_stop), "--views-per-stop");
  if (!o.stops.empty()) {
    const std::vector<double> v = parse_numbers(o.stops, -1, "--stops");
    if (v.size() == 1 && o.stops.find('.') == std::string::npos) {  // a count
      settings.set("mission.stops.count", o.stops, "--stops");
      settings.mission.stops.positions_m.clear();
    } else {  // arm-base x positions
      if (v.size() > 1000) throw InputError("--stops: " + std::to_string(v.size()) + " positions, at most 1000");
      std::string list = "[";
      for (std::size_t i = 0; i < v.size(); ++i) list += (i ? ", " : "") + format_number(v[i], NumberFormat::kDigits17);
      settings.set("mission.stops.positions_m", list + "]", "--stops");
    }
  }
  apply_set_options(settings, o.set);
  job.video = jobs::video_options(o.video, o.video_size, o.video_fps);
  job.world_file = o.world;
  job.seed = o.seed;
  job.out = o.out;
  job.export_dir = o.export_dir;
  job.plots = !o.no_plots;
  job.report = !o.no_report;
  job.strict_colours = o.strict;
  jobs::check_mission_outputs(job);

  const world::World world = jobs::build_world(spec);
  mission::MissionCallbacks cb;
  cb.progress = [](const std::string& m) { spdlog::info("{}", m); };
  cb.stop_requested = [] { return interrupt_requested(); };
  const jobs::MissionJobResult r = jobs::run_mission_job(world, job, cb);
  const records::MissionResult& result = r.result;
  spdlog::info("{}: {} of {} views successful, fruit SC {:.3f}, entropy {:.1f} nats, {:.1f} s simulated, {:.1f} s wall",
               result.complete ? "mission done" : "mission INTERRUPTED (partial results, marked incomplete)",
               result.successful_views(), result.views.size(), result.final_metrics.coverage,
               result.final_metrics.total_entropy, result.sim_time_s, result.wall_time_s);
  std::string split;
  for (const auto& [phase, s] : result.times.totals()) split += " " + phase + " " + std::to_string(s).substr(0, 5) + " s;";
  spdlog::info("wall time by phase:{}", split);
  spdlog::info("wrote {}/ (views.csv, timing.csv, summary.json, settings.yaml, map.csm, map.ply, map.bt{})", o.out,
               r.report_written ? ", report.html" : "");
  if (!result.zero_coverage_reason.empty()) spdlog::warn("fruit SC is 0: {}", result.zero_coverage_reason);
  if (!result.complete || r.plots_interrupted) throw Interrupted();
  if (result.stops_not_reached() > 0)
    throw std::runtime_error("the mission failed: " + result.end_reason + "; its results are in " + o.out);
  if (!r.video_error.empty())
    throw std::runtime_error("the video " + o.video + " is missing (" + r.video_error + "); the other results are in " +
                             o.out);
}

}  // namespace

void add_mission_command(CLI::App& app) {
  auto opt = std::make_shared<MissionCliOptions>();
  CLI::App* sub = app.add_subcommand("mission", "The closed-loop mission: drive the aisle, initial scans, NBV views, map");
  add_options(sub, opt.get(), true);
  sub->callback([opt, sub] { run_mission(*opt, sub); });
}

void add_run_command(CLI::App& app) {
  auto opt = std::make_shared<MissionCliOptions>();
  opt->out = "results";
  CLI::App* sub = app.add_subcommand("run", "Main job: the default mission (method ours) on the default world -> results/");
  add_options(sub, opt.get(), false);
  sub->callback([opt, sub] { run_mission(*opt, sub); });
}

}  // namespace canopy::cli
