// canopy mission / canopy run: the closed-loop mission on the moving robot (mission::Mission),
// and the files it leaves: views.csv, timing.csv, summary.json, settings.yaml, the final map
// (map.csm, map.ply, map.bt), sc_entropy.png and runtime.png, and optionally a video.
// `canopy run` is the default mission (method ours) writing to results/.

#include <spdlog/spdlog.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/io.h"
#include "canopy/common/process.h"
#include "canopy/mission/video.h"
#include "canopy/mapping/map_io.h"
#include "canopy/mission/mission.h"
#include "canopy/nbv/gains.h"
#include "canopy/nbv/ray_sets.h"
#include "canopy/sim/renderer.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_sigint(int) { g_interrupted = true; }

struct MissionCliOptions {
  std::string world = default_world_path();
  std::string config = mission::default_settings_path();
  std::string method = "ours", gain = "osamcep", rays = "ours";
  std::string seg, stops, out, video, video_size = "640x480";
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
        std::string s;
        for (const auto& n : nbv::view_planner_names()) s += (s.empty() ? "" : ", ") + n;
        return s;
      }())->capture_default_str();
  sub->add_option("--gain", o->gain, "Information gain of method ours")->capture_default_str();
  sub->add_option("--rays", o->rays, "Ray set of method ours: ours, dense, sparse")->capture_default_str();
  sub->add_option("--pgt", o->pgt, "Segmentation noise P_gt (1 = none; default: the config's)");
  sub->add_option("--seg", o->seg, "Labels: color or truth (default: the config's)")
      ->check(CLI::IsMember({"color", "truth"}));
  sub->add_option("--seed", o->seed, "Seed of segmentation noise, planners and OMPL")->capture_default_str();
  sub->add_option("--stops", o->stops, "Base stops: a count N (evenly spaced) or arm-base x positions x1,x2,...");
  sub->add_option("--views-per-stop", o->views_per_stop, "Successful NBV views wanted per stop (default: the config's)");
  auto* out = sub->add_option("--out", o->out, "Output folder");
  if (out_required) out->required();
  else out->capture_default_str();
  sub->add_option("--video", o->video, "Also record an H.264 MP4 of the run (chase view, wrist inset, caption)");
  sub->add_option("--video-size", o->video_size, "Video frame size WxH")->capture_default_str();
  sub->add_option("--video-fps", o->video_fps, "Video frames per simulated second")->capture_default_str();
  sub->add_flag("--no-plots", o->no_plots, "Skip sc_entropy.png and runtime.png");
}

// A chase camera behind and above the base, looking ahead along the aisle.
Pose chase_pose(const BasePose& base) {
  const Vec3 heading(std::cos(base.yaw_rad), std::sin(base.yaw_rad), 0.0);
  const Vec3 ground(base.x_m, base.y_m, 0.0);
  return look_at(ground - 1.6 * heading + Vec3(0, 0, 1.9), ground + 0.9 * heading + Vec3(0, 0, 0.6));
}

// Off-screen video: chase view, the last wrist frame's RGB and labels inset, a caption.
class MissionVideo {
 public:
  MissionVideo(const std::string& path, int w, int h, double fps, sim::Simulator& sim, const world::WorldSpec& spec)
      : writer_(path, w, h, fps), classes_(spec.classes) {
    CameraIntrinsics k;
    k.width_px = w;
    k.height_px = h;
    k.cx_px = 0.5 * w;
    k.cy_px = 0.5 * h;
    k.fx_px = k.fy_px = 0.5 * h / std::tan(0.5 * 60.0 * M_PI / 180.0);  // 60 degree vertical field of view
    k.min_range_m = 0.01;
    k.max_range_m = 50.0;
    renderer_ = std::make_unique<sim::Renderer>(sim, k, sim::RenderOptions{true, 1, false});
  }
  void tick(sim::Simulator& sim, const std::string& caption) {
    if (!writer_.ok()) return;  // the encoder died: the run goes on without the video
    Image<Rgb8> frame = renderer_->render_captioned(chase_pose(sim.base_pose()), true, caption);
    if (!wrist_rgb_.empty()) {
      const int iw = frame.width / 4, ih = iw * wrist_rgb_.height / std::max(1, wrist_rgb_.width);
      const Rgb8 white{255, 255, 255};
      blit_scaled(wrist_rgb_, frame.width - iw - 8, frame.height - 2 * ih - 16, iw, ih, &frame, 2, white);
      blit_scaled(wrist_labels_, frame.width - iw - 8, frame.height - ih - 8, iw, ih, &frame, 2, white);
    }
    writer_.write(frame);
  }
  void set_wrist(const LabelledFrame& f) {
    wrist_rgb_ = f.rgb;
    wrist_labels_ = Image<Rgb8>(f.class_id.width, f.class_id.height);
    for (std::size_t i = 0; i < f.class_id.data.size(); ++i) {
      wrist_labels_.data[i] = classes_.color(f.class_id.data[i]);
    }
  }
  VideoWriter& writer() { return writer_; }

 private:
  VideoWriter writer_;
  SemanticClasses classes_;
  std::unique_ptr<sim::Renderer> renderer_;
  Image<Rgb8> wrist_rgb_, wrist_labels_;
};

void run_mission(const MissionCliOptions& o, CLI::App* sub) {
  // Validate every input before any work.
  if (!o.video.empty()) VideoWriter::validate_output_path(o.video);
  const world::WorldSpec spec = load_world_spec(o.world);
  const RobotConfig robot = default_robot_config();
  mission::Settings settings = load_settings(o.config);
  if (sub->count("--pgt")) {
    if (!(std::isfinite(o.pgt) && o.pgt >= 0.0 && o.pgt <= 1.0))
      throw InputError("--pgt: " + std::to_string(o.pgt) + " is not a probability in [0, 1]");
    settings.mapping.extractor.p_gt = o.pgt;
  }
  if (!o.seg.empty()) settings.mapping.extractor.source = perception::label_source_from_string(o.seg, "--seg");
  if (sub->count("--views-per-stop")) {
    if (o.views_per_stop < 0) throw InputError("--views-per-stop: must be >= 0");
    settings.mission.loop.views_per_stop = o.views_per_stop;
  }
  if (!o.stops.empty()) {
    const std::vector<double> v = parse_numbers(o.stops, -1, "--stops");
    if (v.size() == 1 && v[0] >= 1 && v[0] == std::floor(v[0]) && o.stops.find('.') == std::string::npos) {
      settings.mission.stops.count = static_cast<int>(v[0]);
      settings.mission.stops.positions_m.clear();
    } else {
      settings.mission.stops.positions_m = v;
    }
  }
  mission::MissionOptions mo;
  mo.method = o.method;
  mo.gain = o.gain;
  mo.rays = o.rays;
  mo.seed = o.seed;
  nbv::ViewPlannerSettings check;
  check.params = settings.nbv;
  nbv::make_view_planner(o.method, check, "--method");
  nbv::make_gain(o.gain, settings.nbv.gain, "--gain");
  nbv::ray_set(o.rays, "--rays");
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

  const world::World world = world::generate_world(spec);
  spdlog::info("mission: method {}{}, {} plants, {} fruits, P_gt {}, seed {}", o.method,
               o.method == "ours" ? " (" + o.gain + ", rays " + o.rays + ")" : "", world.plants.size(),
               world.truth.fruits.size(), settings.mapping.extractor.p_gt, o.seed);
  StagedDir out(o.out);

  std::unique_ptr<MissionVideo> video;
  mission::MissionCallbacks cb;
  cb.progress = [](const std::string& m) { spdlog::info("{}", m); };
  cb.stop_requested = [] { return g_interrupted.load(); };
  mission::Mission mission(world, settings, mo, [&] {
    mission::MissionCallbacks c = cb;
    if (!o.video.empty()) {
      c.video_period_s = 1.0 / o.video_fps;
      c.video_tick = [&video](sim::Simulator& sim, const std::string& caption) {
        if (video) video->tick(sim, caption);
      };
      c.on_view = [&video](const mission::ViewRecord&, const LabelledFrame& f, const sim::Simulator&) {
        if (video) video->set_wrist(f);
      };
    }
    return c;
  }());
  if (!o.video.empty()) video = std::make_unique<MissionVideo>(o.video, video_w, video_h, o.video_fps, mission.simulator(), spec);

  g_interrupted = false;
  auto previous = std::signal(SIGINT, on_sigint);
  const mission::MissionResult result = mission.run();
  std::signal(SIGINT, previous);

  // Results.
  write_file_atomic(out.path("views.csv"), mission::views_csv(result, o.method));
  write_file_atomic(out.path("timing.csv"), mission::timing_csv(result));
  write_file_atomic(out.path("settings.yaml"), settings.to_yaml_text());
  mapping::save_map(mission.map(), out.path("map.csm"));
  mapping::export_ply(mission.map(), out.path("map.ply"));
  mapping::export_bt(mission.map(), out.path("map.bt"));
  nlohmann::json summary = mission::summary_json(result);
  summary["method"] = {{"name", o.method}, {"gain", o.gain}, {"rays", o.rays}};
  summary["seed"] = o.seed;
  summary["p_gt"] = settings.mapping.extractor.p_gt;
  summary["labels"] = perception::to_string(settings.mapping.extractor.source);
  summary["world"] = {{"file", o.world},
                      {"plants", world.plants.size()},
                      {"fruits", world.truth.fruits.size()},
                      {"triangles", world.triangle_count()},
                      {"spec", spec.to_json()}};
  summary["settings_file"] = "settings.yaml";
  summary["files"] = {"views.csv", "timing.csv", "settings.yaml", "map.csm", "map.ply", "map.bt"};
  bool video_ok = true;
  if (video) {  // an encoder failure loses only the video, not the run
    video_ok = video->writer().close();
    if (video_ok) {
      summary["video"] = {{"file", o.video}, {"frames", video->writer().frames()}};
      spdlog::info("wrote {} ({} frames)", o.video, video->writer().frames());
    } else {
      summary["video"] = {{"file", o.video}, {"error", video->writer().error()}};
      spdlog::error("the video {} is missing: {}", o.video, video->writer().error());
    }
  }
  write_json_atomic(out.path("summary.json"), summary);
  if (!o.no_plots) {
    const std::string script = find_data_file("tools/plot_mission.py");
    const ProcessStatus plot = run_process({"/usr/bin/python3", script, out.working_dir()});
    if (!plot.ok()) spdlog::warn("plots failed (needs python3-matplotlib): {}: {}", script, plot.describe());
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
