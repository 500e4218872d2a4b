#include "canopy/jobs/mission_job.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/timer.h"
#include "canopy/common/interrupt.h"
#include "canopy/jobs/figures.h"
#include "canopy/jobs/run_report.h"
#include "canopy/jobs/world_job.h"
#include "canopy/datasets/nerfstudio.h"
#include "canopy/jobs/test_views.h"
#include "canopy/mission/scan_views.h"
#include "canopy/records/run_folder.h"
#include "canopy/video/video.h"

namespace canopy::jobs {

VideoOptions video_options(const std::string& path, const std::string& size, double fps, const VideoOptionNames& names) {
  VideoOptions v;
  v.path = path;
  v.fps = fps;
  if (path.empty()) return v;
  char x = 0;
  std::istringstream in(size);
  if (!(in >> v.width_px >> x >> v.height_px) || x != 'x' || !in.eof() || v.width_px < 64 || v.height_px < 64 ||
      v.width_px > 1920 || v.height_px > 1080 || v.width_px % 2 || v.height_px % 2)
    throw InputError(names.size + ": '" + size + "' is not WxH with even sizes in [64, 1920] x [64, 1080]");
  if (!(std::isfinite(fps) && fps > 0.0 && fps <= 120.0)) throw InputError(names.fps + ": must be in (0, 120]");
  video::VideoWriter::validate_output_path(path, names.path);
  return v;
}

namespace {

// The export: a staged folder and the frames written into it.
struct Export {
  std::unique_ptr<StagedDir> dir;
  std::unique_ptr<datasets::DatasetExport> dataset;
};

}  // namespace

void check_stops_in_reach(const world::WorldSpec& spec, const settings::StopParams& stops, const RobotConfig& robot) {
  const world::WorldSpec::BaseRange r = base_range(robot, robot::RobotDescription::load_urdf(robot.urdf_path));
  const auto range = [](double lo, double hi) { return fmt::format("[{:g}, {:g}] m", lo, hi); };
  const std::vector<double> xs = mission::stop_positions(stops, spec);
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const double base_x = xs[k] - r.arm_x_m;
    if (base_x < r.x_lower_m || base_x > r.x_upper_m)
      throw InputError(fmt::format("mission.stops.{}: stop {} at x = {:g} m puts the base at x = {:g} m, beyond its "
                                   "joint '{}' range {} ({})",
                                   stops.positions_m.empty() ? "count" : "positions_m", k + 1, xs[k], base_x, r.x_joint,
                                   range(r.x_lower_m, r.x_upper_m), r.source));
  }
  if (stops.base_y_m < r.y_lower_m || stops.base_y_m > r.y_upper_m)
    throw InputError(fmt::format("mission.stops.base_y_m: {:g} m lies beyond the base's joint '{}' range {} ({})",
                                 stops.base_y_m, r.y_joint, range(r.y_lower_m, r.y_upper_m), r.source));
}

void check_mission_outputs(const MissionJobParams& p) {
  check_disjoint_outputs({{p.out, p.out_option},
                          {p.export_dir, "--export"},
                          {p.video.path, "--video"},
                          {p.mcap.path, p.mcap.option}});
  if (!p.out.empty()) StagedDir::check_writable(p.out, "mission", p.out_option);
  if (!p.out.empty()) check_output_place(p.out, p.out_option);
  if (!p.export_dir.empty()) check_output_place(p.export_dir, "--export");
  if (!p.video.path.empty()) check_output_place(p.video.path, "--video");
  if (!p.mcap.path.empty()) check_output_place(p.mcap.path, p.mcap.option);
}

MissionJobResult run_mission_job(const world::World& world, const MissionJobParams& p,
                                 mission::MissionCallbacks cb, const std::function<void(records::MissionResult&)>& amend) {
  check_mission_outputs(p);
  const settings::Settings& settings = p.settings;
  check_stops_in_reach(world.spec, settings.mission.stops);
  check_world_colours(world, settings.mapping.extractor, p.strict_colours);
  const nbv::MethodChoice& method = settings.method;
  spdlog::info("mission: method {}{}, {} plants, {} fruits, P_gt {}, seed {}", method.name,
               method.name == "ours" ? " (" + method.gain + ", rays " + method.rays + ")" : "", world.plants.size(),
               world.truth.fruits.size(), settings.mapping.extractor.p_gt, p.seed);
  std::unique_ptr<StagedDir> out;
  if (!p.out.empty()) out = std::make_unique<StagedDir>(p.out, "mission", StagedDir::Mode::kReplace, p.out_option);
  Export ex;
  if (!p.export_dir.empty()) {
    ex.dir = std::make_unique<StagedDir>(p.export_dir, "dataset", StagedDir::Mode::kReplace, "--export");
    ex.dataset = std::make_unique<datasets::DatasetExport>(ex.dir->working_dir(), world.spec.classes, world.spec.camera);
  }

  // The video outlives the mission; its callbacks find it (and the map inset the mission's map)
  // once both exist.
  const bool filmed = !p.video.path.empty();
  std::unique_ptr<video::MissionVideo> video;
  // The ROS 2 recording, written as the mission runs; stamps count from its start.
  const std::int64_t started_ns = wall_clock_now_ns();
  std::unique_ptr<MissionMcap> mcap;
  if (!p.mcap.path.empty()) mcap = std::make_unique<MissionMcap>(p.mcap, world, settings);
  const mission::Mission* running = nullptr;
  // The caller's own tick (Python's on_state) runs after the video's, at the video's period.
  if (filmed || mcap) {
    // The recording's state ticks at the video's rate when there is one (it keeps its own period).
    if (filmed) cb.video_period_s = 1.0 / p.video.fps;
    else if (cb.video_period_s <= 0.0 || !cb.video_tick) cb.video_period_s = p.mcap.state_period_s;
    cb.video_tick = [&video, &mcap, caller = std::move(cb.video_tick)](sim::Simulator& sim, const std::string& caption) {
      if (video) video->tick(sim, caption);
      if (mcap) mcap->state(sim);
      if (caller) caller(sim, caption);
    };
  }
  if (filmed || ex.dataset || p.on_view || mcap)  // (a callback that reads the map waits for each scan's insertion)
    cb.on_view = [&video, &ex, &running, &p, &mcap](const records::ViewRecord& v, const LabelledFrame& f,
                                                   const sim::Simulator& sim) {
      if (video) video->set_wrist(f);
      if (video && running) video->set_map(running->map(), sim.base_pose());
      if (ex.dataset) ex.dataset->add_train(f);
      if (mcap && running) mcap->view(v, f, sim, running->map());
      if (p.on_view && running) p.on_view(v, f, sim, running->map());
    };
  // What the report replays, recorded beside the mission (replay.h).
  std::unique_ptr<records::MapReplay> replay;
  if (out && p.report) {
    if (report_libraries_present()) {
      replay = std::make_unique<records::MapReplay>(world.spec.classes);
      cb.replay = replay.get();
    } else {
      spdlog::warn("report.html skipped (needs Debian's libjs-three; run tools/deps.sh)");
    }
  }
  // The recording colours fruits by the pipeline's per-view coverage, recorded beside the mission.
  std::unique_ptr<records::MapReplay> mcap_replay;
  if (mcap && !cb.replay) {
    mcap_replay = std::make_unique<records::MapReplay>(world.spec.classes);
    cb.replay = mcap_replay.get();
  }
  if (mcap) mcap->follow_coverage(cb.replay);
  const std::function<bool()> stop_requested = cb.stop_requested;
  mission::Mission mission(world, settings, p.seed, cb);
  running = &mission;
  if (filmed)
    video = std::make_unique<video::MissionVideo>(p.video.path, p.video.width_px, p.video.height_px, p.video.fps,
                                                    mission.simulator(), world.spec.classes);
  if (stop_requested && stop_requested())
    throw Interrupted("interrupted while setting up the mission; nothing was written");
  if (mcap) mcap->start(mission.simulator(), p.mcap.epoch_ns.value_or(started_ns));

  MissionJobResult r;
  r.result = mission.run();
  const int signals_at_end = interrupt_count();  // a later signal skips the plots (docs/commands.md)
  if (amend) amend(r.result);
  records::RunContext context;
  context.seed = p.seed;
  context.world_file = p.world_file;
  context.world = &world;
  context.started_unix_ns = started_ns;
  if (video) {  // an encoder failure loses only the video, not the run
    if (video->writer().close()) {
      r.video_frames = video->writer().frames();
      context.video = {{"file", p.video.path}, {"frames", r.video_frames}};
      spdlog::info("wrote {} ({} frames)", p.video.path, r.video_frames);
    } else {
      r.video_error = video->writer().error();
      context.video = {{"file", p.video.path}, {"error", r.video_error}};
      spdlog::error("the video {} is missing: {}", p.video.path, r.video_error);
    }
  }
  if (mcap && r.result.complete) {  // an interrupted mission leaves no recording, as no bag
    r.mcap = mcap->close();
    r.mcap_written = true;
    spdlog::info("wrote {} ({} messages, {:.1f} MB; stamps from {:.3f} s since 1970)", p.mcap.path, r.mcap.messages,
                 r.mcap.file_bytes / 1e6, mcap->epoch_ns() / 1e9);
    context.recording = {{"file", p.mcap.path},
                         {"epoch_unix_ns", mcap->epoch_ns()},
                         {"messages", r.mcap.messages},
                         {"compression", p.mcap.compression == ros2::Compression::kNone ? "none"
                                                                          : std::string(ros2::compression_name(p.mcap.compression))}};
  }
  r.summary = out ? records::write_run_folder(out->working_dir(), r.result, settings, mission.map(), context)
                  : records::run_summary(r.result, settings, context);
  // The report's data: report.html shows it, and the plots are drawn from it.
  RunReport report;
  if (out && (replay || p.plots)) report = mission_report_data(r.result, settings, world, r.summary);
  if (out && replay) {
    const Stopwatch watch;
    report.robot_shapes = robot_shapes_json(robot::RobotDescription::load_urdf(mission.simulator().robot_config().urdf_path));
    write_run_report(out->working_dir(), report, *replay);
    r.report_written = true;
    spdlog::info("report.html: {} voxel changes over {} views, recorded in {:.2f} s beside the mission, written in {:.2f} s",
                 replay->change_count(), replay->scans().size(), replay->seconds(), watch.seconds());
  }
  if (out && p.plots) {
    if (interrupt_count() > signals_at_end) {  // a signal while the run was being saved: published without its plots
      spdlog::warn("the plots of {} are skipped: interrupted while saving the run", p.out);
      r.plots_interrupted = true;
    } else {
      const Stopwatch watch;
      write_figures(out->working_dir(), mission_figures(report.data, report.wall));
      spdlog::info("sc_entropy.svg, runtime.svg: drawn in {:.3f} s", watch.seconds());
    }
  }
  if (ex.dataset && r.result.complete) {
    render_test_views(*ex.dataset, mission.simulator(), world, default_test_ring());
    ex.dataset->finish({{"command", "mission"}, {"world", p.world_file}, {"method", method.name}, {"seed", p.seed}});
    ex.dir->commit();
    r.dataset_written = true;
    r.dataset_train = ex.dataset->train_count();
    r.dataset_test = ex.dataset->test_count();
    spdlog::info("wrote {}/ (nerfstudio dataset: {} training views, {} held-out views)", p.export_dir, r.dataset_train,
                 r.dataset_test);
  }
  if (p.keep_map) r.map = std::make_shared<mapping::SemanticOcTree>(mission.map());
  if (out) out->commit();
  return r;
}

}  // namespace canopy::jobs
