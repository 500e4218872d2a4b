// canopy run: the main job (./tools/run.sh). Generates the world, drives the robot along the
// aisle, renders the wrist camera's views of both rows and writes images and a summary.

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <set>

#include "canopy/common/frame_io.h"
#include "canopy/common/io.h"
#include "canopy/common/video.h"
#include "canopy/mapping/map_io.h"
#include "canopy/mapping/mapping_config.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/mission/aisle_survey.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {

// A view from behind and above the aisle start, looking down the aisle.
Pose overview_pose(const world::WorldSpec& spec) {
  const double x_mid = spec.rows.x_start_m + 0.5 * (spec.rows.plants_per_row - 1) * spec.rows.plant_spacing_m;
  return look_at(Vec3(spec.robot_start.x_m - 1.6, 0.0, 2.3), Vec3(x_mid, 0.0, 0.5));
}

// A chase camera behind and above the base, looking ahead along the aisle.
Pose chase_pose(const BasePose& base) {
  const Vec3 heading(std::cos(base.yaw_rad), std::sin(base.yaw_rad), 0.0);
  const Vec3 ground(base.x_m, base.y_m, 0.0);
  return look_at(ground - 1.4 * heading + Vec3(0, 0, 1.9), ground + 0.9 * heading + Vec3(0, 0, 0.6));
}

}  // namespace

void add_run_command(CLI::App& app) {
  struct Options {
    std::string world = default_world_path();
    std::string out = "results";
    std::string video;
    std::string mapping_config = find_data_file("configs/mapping.yaml");
    double video_fps = 25.0;
    bool shadows = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand("run", "Main job: drive the aisle, render the wrist camera's views, write results");
  sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  sub->add_option("--out", opt->out, "Results folder")->capture_default_str();
  sub->add_flag("--shadows", opt->shadows, "Shadows in RGB images");
  sub->add_option("--video", opt->video, "Also write an MP4 (H.264) of the run, seen from behind the robot, to this file");
  sub->add_option("--mapping-config", opt->mapping_config, "Mapping config for the survey's semantic map")
      ->capture_default_str();
  sub->add_option("--video-fps", opt->video_fps, "Video frames per simulated second")->capture_default_str();
  sub->callback([opt] {
    const auto wall0 = std::chrono::steady_clock::now();
    if (!opt->video.empty()) VideoWriter::validate_output_path(opt->video);  // fail before the run
    const world::WorldSpec spec = load_world_spec(opt->world);
    const mapping::MappingConfig mapping_cfg = mapping::MappingConfig::load(opt->mapping_config);
    const world::World world = world::generate_world(spec);
    spdlog::info("generated {} plants, {} fruits, {} triangles", world.plants.size(), world.truth.fruits.size(),
                 world.triangle_count());
    sim::Simulator sim(world, default_robot_config());
    sim::RenderOptions ro;
    ro.shadows = opt->shadows;
    sim::Renderer renderer(sim, spec.camera, ro);
    StagedDir out(opt->out);

    // Overview of the scene with the robot at the start of the aisle.
    {
      sim::Renderer overview(sim, spec.camera, sim::RenderOptions{true, 1});
      write_png(out.path("overview.png"), overview.render(overview_pose(spec), true, false).rgb);
    }
    mission::SurveyCallbacks callbacks;
    callbacks.progress = [](const std::string& m) { spdlog::info("{}", m); };
    std::unique_ptr<VideoWriter> video;
    std::unique_ptr<sim::Renderer> video_renderer;
    if (!opt->video.empty()) {
      CameraIntrinsics video_camera = spec.camera;  // same size as the offscreen buffer
      video = std::make_unique<VideoWriter>(opt->video, video_camera.width_px, video_camera.height_px, opt->video_fps);
      video_renderer = std::make_unique<sim::Renderer>(sim, video_camera, sim::RenderOptions{true, 1});
      callbacks.video_period_s = 1.0 / opt->video_fps;
      callbacks.video_tick = [&](double) {
        video->write(video_renderer->render(chase_pose(sim.base_pose()), true, false).rgb);
      };
    }
    const mission::SurveyResult survey = mission::run_aisle_survey(sim, renderer, spec, mission::SurveyParams{}, callbacks);
    if (video) {  // an encoder failure loses only the video, not the run
      if (video->close()) spdlog::info("wrote {} ({} frames)", opt->video, video->frames());
      else spdlog::error("the video {} is missing: {}", opt->video, video->error());
    }

    // The survey's views, mapped into a semantic octree as the paper's predefined scan.
    mapping::SemanticOcTree map(mapping_cfg.map, spec.classes);
    mapping::ScanInserter inserter(map);
    perception::SemanticExtractor extractor(mapping_cfg.extractor, spec.classes);
    double insert_ms = 0.0;
    for (const auto& o : survey.observations) insert_ms += inserter.insert(extractor.extract(o.frame)).ms_total;
    const mapping::MapMetrics metrics = mapping::evaluate_map(map, world.truth, mapping_cfg.metrics);
    mapping::save_map(map, out.path("map.csm"));
    const std::size_t occupied = mapping::export_ply(map, out.path("map.ply"));
    spdlog::info("semantic map of the survey: fruit surface coverage {:.3f}, fruit entropy {:.1f} nats, {} occupied voxels",
                 metrics.coverage, metrics.total_entropy, occupied);

    nlohmann::json obs = nlohmann::json::array();
    for (const auto& o : survey.observations) {
      char prefix[64];
      std::snprintf(prefix, sizeof(prefix), "stop%d_%s_", o.stop, o.side.c_str());
      write_frame(out.path(prefix), o.frame, spec.classes);
      std::vector<long> class_pixels(spec.classes.names.size(), 0);
      long valid = 0;
      std::set<int> instances;
      for (size_t i = 0; i < o.frame.class_id.data.size(); ++i) {
        ++class_pixels[o.frame.class_id.data[i]];
        valid += o.frame.depth_m.data[i] > 0.f;
        if (o.frame.instance.data[i] != kNoInstance) instances.insert(o.frame.instance.data[i]);
      }
      nlohmann::json pixels;
      for (size_t c = 0; c < class_pixels.size(); ++c) pixels[spec.classes.names[c]] = class_pixels[c];
      obs.push_back({{"files", std::string(prefix) + "{rgb,depth,labels,instances}.png"},
                     {"stop", o.stop},
                     {"side", o.side},
                     {"base", {o.base.x_m, o.base.y_m, o.base.yaw_rad}},
                     {"arm_error_rad", o.arm_error_rad},
                     {"arm_settle_time_s", o.settle_time_s},
                     {"valid_depth_pixels", valid},
                     {"class_pixels", pixels},
                     {"fruits_in_view", std::vector<int>(instances.begin(), instances.end())}});
    }
    nlohmann::json summary;
    summary["world"] = {{"file", opt->world}, {"name", spec.name}, {"seed", spec.seed},
                        {"plants", world.plants.size()}, {"fruits", world.truth.fruits.size()},
                        {"triangles", world.triangle_count()}};
    summary["all_stops_reached"] = survey.all_stops_reached;
    summary["stop_position_error_m"] = survey.stop_position_error_m;
    summary["simulated_time_s"] = survey.sim_time_s;
    summary["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    summary["observations"] = obs;
    summary["map"] = {{"files", {"map.csm", "map.ply"}},
                      {"labels", perception::to_string(mapping_cfg.extractor.source)},
                      {"p_gt", mapping_cfg.extractor.p_gt},
                      {"occupied_voxels", occupied},
                      {"ms_per_insertion", insert_ms / std::max<std::size_t>(1, survey.observations.size())},
                      {"metrics", metrics.to_json()}};
    write_json_atomic(out.path("summary.json"), summary);
    out.commit();
    spdlog::info("wrote {}/summary.json, map.csm, map.ply, overview.png and {} views ({:.1f} s simulated, {:.1f} s wall)", opt->out,
                 survey.observations.size(), survey.sim_time_s, summary["wall_time_s"].get<double>());
    if (!survey.all_stops_reached) throw std::runtime_error("the base did not reach every stop (see summary.json)");
    if (video && !video->ok())
      throw std::runtime_error("the video " + opt->video + " is missing (" + video->error() + "); the other results are in " +
                               opt->out);
  });
}

}  // namespace canopy::cli
