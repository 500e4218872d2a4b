// canopy mission / canopy run: the closed-loop mission on the moving robot (mission::Mission),
// and the files it leaves: views.csv, timing.csv, summary.json, settings.yaml, the final map
// (map.csm, map.ply, map.bt), sc_entropy.png and runtime.png, and optionally a video.
// `canopy run` is the default mission (method ours) writing to results/.

#include <spdlog/spdlog.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/interrupt.h"
#include "canopy/common/io.h"
#include "canopy/common/process.h"
#include "canopy/mission/dataset_export.h"
#include "canopy/mission/mission.h"
#include "canopy/mission/run_folder.h"
#include "canopy/mission/video.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {


struct MissionCliOptions {
  std::string world = default_world_path();
  std::string config = mission::default_settings_path();
  std::string method = "ours", gain = "osamcep", rays = "ours";  // override the bundle's `method` when given
  std::vector<std::string> set;
  std::string seg, stops, out, video, video_size = "640x480", export_dir;
  double pgt = -1.0;  // < 0: the config's
  int views_per_stop = -1;
  std::uint64_t seed = 1;
  double video_fps = 25.0;
  bool no_plots = false;
};

void add_options(CLI::App* sub, MissionCliOptions* o, bool out_required) {
  sub->add_option("--world", o->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--config", o->config, kConfigHelp)->capture_default_str();
  sub->add_option("--method", o->method, "View planner: " + [] {
        mission::register_oracle_planners();
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
  sub->add_flag("--no-plots", o->no_plots, "Skip sc_entropy.png and runtime.png");
  sub->add_option("--export", o->export_dir,
                  "Also write a NeRF / Gaussian-splatting dataset (nerfstudio layout) of every successful view, "
                  "with held-out ring views, into this folder");
}

void run_mission(const MissionCliOptions& o, CLI::App* sub) {
  // Ctrl-C and SIGTERM from here on: the views so far are saved, marked incomplete.
  const InterruptScope interrupts;
  // Validate every input before any work.
  if (!o.video.empty()) mission::VideoWriter::validate_output_path(o.video);
  const world::WorldSpec spec = load_world_spec(o.world);
  mission::Settings settings = load_settings(o.config);
  if (sub->count("--method")) settings.set("method.name", o.method, "--method");
  if (sub->count("--gain")) settings.set("method.gain", o.gain, "--gain");
  if (sub->count("--rays")) settings.set("method.rays", o.rays, "--rays");
  // Flags set settings by their keys: the same limits as in a settings file.
  if (sub->count("--pgt")) settings.set("mapping.extractor.p_gt", format_number(o.pgt, "%.17g"), "--pgt");
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
      for (std::size_t i = 0; i < v.size(); ++i) list += (i ? ", " : "") + format_number(v[i], "%.17g");
      settings.set("mission.stops.positions_m", list + "]", "--stops");
    }
  }
  for (const std::string& s : o.set) {
    const mission::SettingOverride kv = mission::parse_override(s, "--set");
    settings.set(kv.first, kv.second, "--set " + s);
  }
  int video_w = 0, video_h = 0;
  if (!o.video.empty()) {
    char x = 0;
    std::istringstream in(o.video_size);
    if (!(in >> video_w >> x >> video_h) || x != 'x' || !in.eof() || video_w < 64 || video_h < 64 || video_w > 1920 ||
        video_h > 1080 || video_w % 2 || video_h % 2)
      throw InputError("--video-size: '" + o.video_size + "' is not WxH with even sizes in [64, 1920] x [64, 1080]");
    if (!(std::isfinite(o.video_fps) && o.video_fps > 0.0 && o.video_fps <= 120.0))
      throw InputError("--video-fps: must be in (0, 120]");
  }

  const world::World world = build_world(spec);
  check_world_colours(world, settings.mapping.extractor);
  const nbv::MethodChoice& method = settings.method;
  spdlog::info("mission: method {}{}, {} plants, {} fruits, P_gt {}, seed {}", method.name,
               method.name == "ours" ? " (" + method.gain + ", rays " + method.rays + ")" : "", world.plants.size(),
               world.truth.fruits.size(), settings.mapping.extractor.p_gt, o.seed);
  StagedDir out(o.out, "mission");
  std::unique_ptr<StagedDir> export_out;
  std::unique_ptr<mission::DatasetExport> dataset;
  if (!o.export_dir.empty()) {
    export_out = std::make_unique<StagedDir>(o.export_dir, "dataset", StagedDir::Mode::kReplace, "--export");
    dataset = std::make_unique<mission::DatasetExport>(export_out->working_dir(), spec.classes, spec.camera);
  }

  std::unique_ptr<mission::MissionVideo> video;
  mission::MissionCallbacks cb;
  cb.progress = [](const std::string& m) { spdlog::info("{}", m); };
  cb.stop_requested = [] { return interrupt_requested(); };
  if (!o.video.empty()) {
    cb.video_period_s = 1.0 / o.video_fps;
    cb.video_tick = [&video](sim::Simulator& sim, const std::string& caption) {
      if (video) video->tick(sim, caption);
    };
  }
  const mission::Mission* running = nullptr;  // the map inset reads its map
  if (!o.video.empty() || dataset)  // (a callback that reads the map waits for each scan's insertion)
    cb.on_view = [&video, &dataset, &running](const mission::ViewRecord&, const LabelledFrame& f,
                                              const sim::Simulator& sim) {
      if (video) video->set_wrist(f);
      if (video && running) video->set_map(running->map(), sim.base_pose());
      if (dataset) dataset->add_train(f);
    };
  mission::Mission mission(world, settings, o.seed, cb);
  running = &mission;
  if (!o.video.empty())
    video = std::make_unique<mission::MissionVideo>(o.video, video_w, video_h, o.video_fps, mission.simulator(),
                                                    spec.classes);

  if (interrupt_requested()) throw Interrupted("interrupted while setting up the mission; nothing was written");
  const mission::MissionResult result = mission.run();

  // Results.
  mission::RunContext context;
  context.seed = o.seed;
  context.world_file = o.world;
  context.world = &world;
  bool video_ok = true;
  if (video) {  // an encoder failure loses only the video, not the run
    video_ok = video->writer().close();
    if (video_ok) {
      context.video = {{"file", o.video}, {"frames", video->writer().frames()}};
      spdlog::info("wrote {} ({} frames)", o.video, video->writer().frames());
    } else {
      context.video = {{"file", o.video}, {"error", video->writer().error()}};
      spdlog::error("the video {} is missing: {}", o.video, video->writer().error());
    }
  }
  mission::write_run_folder(out.working_dir(), result, settings, mission.map(), context);
  if (!o.no_plots) {
    const std::string script = find_data_file("tools/plot_mission.py");
    const ProcessStatus plot = run_process({"/usr/bin/python3", script, out.working_dir()});
    if (!plot.ok()) spdlog::warn("plots failed (needs python3-matplotlib): {}: {}", script, plot.describe());
  }
  if (dataset && result.complete) {
    dataset->render_test_views(mission.simulator(), world, mission::default_test_ring());
    dataset->finish({{"command", "mission"}, {"world", o.world}, {"method", settings.method.name}, {"seed", o.seed}});
    export_out->commit();
    spdlog::info("wrote {}/ (nerfstudio dataset: {} training views, {} held-out views)", o.export_dir,
                 dataset->train_count(), dataset->test_count());
  }
  out.commit();
  spdlog::info("{}: {} of {} views successful, fruit SC {:.3f}, entropy {:.1f} nats, {:.1f} s simulated, {:.1f} s wall",
               result.complete ? "mission done" : "mission INTERRUPTED (partial results, marked incomplete)",
               result.successful_views(), result.views.size(), result.final_metrics.coverage,
               result.final_metrics.total_entropy, result.sim_time_s, result.wall_time_s);
  std::string split;
  for (const auto& [phase, s] : result.times.totals()) split += " " + phase + " " + std::to_string(s).substr(0, 5) + " s;";
  spdlog::info("wall time by phase:{}", split);
  spdlog::info("wrote {}/ (views.csv, timing.csv, summary.json, settings.yaml, map.csm, map.ply, map.bt)", o.out);
  if (!result.zero_coverage_reason.empty()) spdlog::warn("fruit SC is 0: {}", result.zero_coverage_reason);
  if (!result.complete) throw Interrupted();
  if (!video_ok)
    throw std::runtime_error("the video " + o.video + " is missing (" + video->writer().error() + "); the other results are in " +
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
