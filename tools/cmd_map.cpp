// canopy map: render views of a world with a free-floating camera, insert each into the
// semantic map, and after every view write the map, its PLY and .bt exports and metrics.json.
// With --frames DIR: map a recorded sequence (canopy or TUM layout) instead of a world.

#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>

#include "canopy/common/error.h"
#include "canopy/common/interrupt.h"
#include "canopy/common/io.h"
#include "canopy/common/timer.h"
#include "canopy/datasets/frame_sequence.h"
#include "canopy/datasets/sequence_mapping.h"
#include "canopy/mapping/map_io.h"
#include "canopy/mapping/frame_mapping.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/mission/dataset_export.h"
#include "canopy/mission/view_columns.h"
#include "canopy/sim/renderer.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {

nlohmann::json insert_json(const mapping::InsertStats& s, const perception::ExtractStats& e) {
  return {{"points", s.points},
          {"skipped_bad_depth", e.bad_depth},
          {"skipped_out_of_range", e.out_of_range},
          {"carved_missing_depth", e.missing_depth},
          {"skipped_bad_label", e.bad_label + s.bad_label},
          {"skipped_bad_point", s.bad_point + s.outside_map},
          {"masks", e.masks},
          {"masks_flipped", e.masks_flipped},
          {"hit_voxels", s.hit_voxels},
          {"free_voxels", s.free_voxels},
          {"saturated_updates", s.tree.saturated},
          {"ms_insert", s.ms_total},
          {"ms_filter", s.ms_filter},
          {"ms_raycast", s.ms_raycast},
          {"ms_update", s.ms_update}};
}

struct MapOptions {
  std::string world = default_world_path();
  std::string views = "ring";
  std::string config = mission::default_settings_path();
  std::string seg;
  double pgt = -1.0;
  std::string out;
  std::string frames, intrinsics, label_colors;
  std::string export_dir;
  double max_dt_s = datasets::FrameReaderOptions{}.max_time_diff_s;
};

// canopy map --frames: no world, no ground truth; the map and what each frame gave.
void map_recorded(const MapOptions& opt, mission::Settings bundle) {
  mission::MappingSettings& cfg = bundle.mapping;
  datasets::FrameReaderOptions reader;
  reader.intrinsics_file = opt.intrinsics;
  reader.label_colors_file = opt.label_colors;
  reader.max_time_diff_s = opt.max_dt_s;
  reader.label_images = cfg.extractor.source == perception::LabelSource::kTruth;
  const datasets::FrameSequence frames = datasets::FrameSequence::open(opt.frames, reader);
  StagedDir out(opt.out, "map");
  mapping::SemanticOcTree map(cfg.map, frames.classes());
  mapping::ScanInserter inserter(map);
  perception::SemanticExtractor extractor(cfg.extractor, frames.classes());
  write_file_atomic(out.path("settings.yaml"), bundle.to_yaml_text());
  YAML::Node run;
  run["command"] = "map";
  run["frames"] = opt.frames;
  run["layout"] = datasets::to_string(frames.layout());
  run["labels"] = reader.label_images ? "label images" : "color";
  run["classes"] = frames.classes().names;
  run["max_time_diff_s"] = opt.max_dt_s;
  write_file_atomic(out.path("run.yaml"), yaml_text(run));
  spdlog::info("mapping {} frames ({} layout, {} skipped while pairing), labels {}", frames.size(),
               datasets::to_string(frames.layout()), frames.skipped().size(), reader.label_images ? "from images" : "color");
  for (const std::string& note : frames.notes()) spdlog::warn("{}: {}", opt.frames, note);
  const datasets::SequenceMapResult r = datasets::map_sequence(
      frames, extractor, inserter,
      [&](const mapping::FrameMapStep& s) {
        if (s.mapped)
          std::fprintf(stderr, "frame %s: %zu points, insert %.1f ms\n", s.name.c_str(), s.extract.points,
                       s.insert.ms_total);
        else
          std::fprintf(stderr, "frame %s: skipped (%s)\n", s.name.c_str(), s.skip_reason.c_str());
      },
      [] { return interrupt_requested(); });
  if (!r.complete && r.mapped == 0) throw Interrupted("interrupted before the first frame; nothing was written");
  if (r.mapped == 0) throw InputError(opt.frames + ": no frame could be mapped (" + std::to_string(r.skipped.size()) + " skipped)");
  mapping::save_map(map, out.path("map.csm"));
  const std::size_t occupied = mapping::export_ply(map, out.path("map.ply"));
  mapping::export_bt(map, out.path("map.bt"));
  nlohmann::json steps = nlohmann::json::array();
  for (const mapping::FrameMapStep& s : r.steps) {
    nlohmann::json j = {{"frame", s.name}, {"mapped", s.mapped}};
    if (s.mapped) j["insert"] = insert_json(s.insert, s.extract);
    else j["skip_reason"] = s.skip_reason;
    steps.push_back(j);
  }
  nlohmann::json skipped = nlohmann::json::array();
  for (const datasets::SkippedFrame& s : r.skipped) skipped.push_back({{"frame", s.name}, {"reason", s.reason}});
  write_json_atomic(out.path("frames.json"), {{"complete", r.complete},
                                              {"notes", frames.notes()},
                                              {"frames_mapped", r.mapped},
                                              {"frames_skipped", r.skipped.size()},
                                              {"skipped_by_reason", datasets::count_reasons(r.skipped)},
                                              {"skipped", skipped},
                                              {"occupied_voxels", occupied},
                                              {"steps", steps}});
  out.commit();
  if (!r.complete)
    throw Interrupted("interrupted after " + std::to_string(r.mapped) + " frames; the map so far is saved in " + opt.out +
                      " (frames.json \"complete\": false)");
  std::printf("mapped %zu frames (%zu skipped): %zu occupied voxels; wrote %s\n", r.mapped, r.skipped.size(),
              occupied, opt.out.c_str());
}

}  // namespace

void add_map_command(CLI::App& app) {
  auto opt = std::make_shared<MapOptions>();
  CLI::App* sub = app.add_subcommand("map", "Map a world from camera views: semantic map, PLY, .bt and metrics.json");
  auto* world = sub->add_option("--world", opt->world, "World file (YAML)")->capture_default_str();
  auto* views = sub->add_option("--views", opt->views, "Camera poses: 'ring', 'aisle' or a file of 'x y z qw qx qy qz' lines")
      ->capture_default_str();
  auto* frames = sub->add_option("--frames", opt->frames,
                                 "Map a recorded sequence instead of a world: canopy frame folders (what 'canopy "
                                 "render' writes) or a TUM RGB-D folder (rgb.txt, depth.txt, groundtruth.txt)");
  frames->excludes(world)->excludes(views);
  sub->add_option("--intrinsics", opt->intrinsics, "--frames, TUM: camera YAML (default: DIR/camera.yaml)")
      ->needs(frames);
  sub->add_option("--label-colors", opt->label_colors,
                  "--frames with --seg truth: class-colour table of the label images (YAML; default: the "
                  "classes' drawing colours)")
      ->needs(frames);
  sub->add_option("--max-dt", opt->max_dt_s, "--frames, TUM: largest RGB-depth and depth-pose time difference [s]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber)
      ->needs(frames);
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_option("--seg", opt->seg, "Labels: color (HSV segmentation) or truth (renderer; with --frames: the label images); default from config")
      ->check(CLI::IsMember({"color", "truth"}));
  sub->add_option("--pgt", opt->pgt, "Probability a mask keeps its class (1 = no noise); default from config")
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->add_option("--export", opt->export_dir,
                  "Also write a NeRF / Gaussian-splatting dataset (nerfstudio layout) of the views, with held-out "
                  "ring views, into this folder")
      ->excludes(frames);
  sub->callback([opt] {
    // Ctrl-C and SIGTERM: the views mapped so far are saved, marked incomplete.
    const InterruptScope interrupts;
    mission::Settings bundle = load_settings(opt->config);
    mission::MappingSettings& cfg = bundle.mapping;
    if (!opt->seg.empty()) bundle.set("mapping.extractor.source", opt->seg, "--seg");
    if (opt->pgt >= 0.0) bundle.set("mapping.extractor.p_gt", format_number(opt->pgt, "%.17g"), "--pgt");
    if (!opt->frames.empty()) return map_recorded(*opt, bundle);
    const world::WorldSpec spec = load_world_spec(opt->world);
    const world::World world = build_world(spec);
    check_world_colours(world, cfg.extractor);
    const std::vector<Pose> views = evaluation::views_from_spec(opt->views, world);
    StagedDir out(opt->out, "map");
    std::unique_ptr<StagedDir> export_out;
    std::unique_ptr<mission::DatasetExport> dataset;
    if (!opt->export_dir.empty()) {
      export_out = std::make_unique<StagedDir>(opt->export_dir, "dataset", StagedDir::Mode::kReplace, "--export");
      dataset = std::make_unique<mission::DatasetExport>(export_out->working_dir(), spec.classes, spec.camera);
    }

    sim::Simulator sim(world, default_robot_config());
    sim::Renderer renderer(sim, spec.camera);
    mapping::SemanticOcTree map(cfg.map, spec.classes);
    mapping::ScanInserter inserter(map);
    perception::SemanticExtractor extractor(cfg.extractor, spec.classes);
    write_file_atomic(out.path("settings.yaml"), bundle.to_yaml_text());  // a loadable --config
    YAML::Node run = run_record("map", spec);
    run["views"] = opt->views;
    nlohmann::json poses = nlohmann::json::array();
    for (const Pose& T : views) poses.push_back(pose_to_json(T));
    run["view_poses"] = YAML::Load(poses.dump());
    write_file_atomic(out.path("run.yaml"), yaml_text(run));
    spdlog::info("mapping {} views ({}), labels {}, P_gt {}", views.size(), opt->views,
                 perception::to_string(cfg.extractor.source), cfg.extractor.p_gt);

    nlohmann::json history = nlohmann::json::array();
    double insert_ms_sum = 0.0;
    nlohmann::json last;
    std::size_t done = 0;
    for (std::size_t i = 0; i < views.size(); ++i) {
      if (interrupt_requested()) break;
      const Stopwatch render_watch;
      const LabelledFrame frame = renderer.render_free_camera(views[i]);
      const double ms_render = render_watch.ms();
      const mapping::FrameMapStep fs = mapping::map_frame(frame, extractor, inserter);
      if (dataset) dataset->add_train(frame);
      const mapping::InsertStats& st = fs.insert;
      insert_ms_sum += st.ms_total;
      const evaluation::MapMetrics m = evaluation::evaluate_map(map, world.truth, cfg.metrics);
      mapping::save_map(map, out.path("map.csm"));
      const std::size_t occupied = mapping::export_ply(map, out.path("map.ply"));
      mapping::export_bt(map, out.path("map.bt"));

      nlohmann::json step = mission::map_history_metrics(m);  // the view columns' map figures
      step.update({{"view", i}, {"pose", pose_to_json(views[i])}, {"ms_render", ms_render},
                   {"insert", insert_json(st, fs.extract)}});
      history.push_back(step);
      nlohmann::json j = m.to_json();
      j["world"] = spec.name;
      j["views_done"] = i + 1;
      j["views_total"] = views.size();
      j["labels"] = perception::to_string(cfg.extractor.source);
      j["p_gt"] = cfg.extractor.p_gt;
      j["noise"] = perception::to_string(cfg.extractor.noise);
      j["ms_per_insertion"] = insert_ms_sum / double(i + 1);
      j["history"] = history;
      j["complete"] = i + 1 == views.size();
      write_json_atomic(out.path("metrics.json"), j);
      last = j;
      done = i + 1;
      std::fprintf(stderr,
                   "view %zu/%zu: %zu points, insert %.1f ms, coverage %.3f, fruit entropy %.1f, %zu occupied "
                   "voxels\n",
                   i + 1, views.size(), fs.extract.points, st.ms_total, m.coverage, m.total_entropy, occupied);
    }
    if (done == 0) throw Interrupted("interrupted before the first view; nothing was written");
    if (done < views.size()) {  // interrupted: what is mapped is saved, marked incomplete
      last["complete"] = false;
      write_json_atomic(out.path("metrics.json"), last);
      out.commit();
      throw Interrupted("interrupted after " + std::to_string(done) + " of " + std::to_string(views.size()) +
                        " views; the map so far is saved in " + opt->out + " (metrics.json \"complete\": false)");
    }
    if (dataset) {
      dataset->render_test_views(sim, world, mission::default_test_ring());
      dataset->finish({{"command", "map"}, {"world", opt->world}, {"views", opt->views}});
      export_out->commit();
      std::printf("wrote %s (nerfstudio dataset: %zu training views, %zu held-out views)\n", opt->export_dir.c_str(),
                  dataset->train_count(), dataset->test_count());
    }
    out.commit();
    std::printf("mapped %zu views: coverage %.3f, fruit entropy %.1f, %.1f ms per insertion; wrote %s\n",
                views.size(), history.back()["coverage"].get<double>(), history.back()["total_entropy"].get<double>(),
                insert_ms_sum / double(views.size()), opt->out.c_str());
  });
}

}  // namespace canopy::cli
