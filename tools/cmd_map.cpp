// canopy map: render views of a world with a free-floating camera, insert each into the
// semantic map, and after every view write the map, its PLY and .bt exports and metrics.json
// (jobs::map_views, canopy/jobs/map_job.h). With --frames DIR: map a recorded sequence (canopy
// or TUM layout) instead of a world.

#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>

#include "canopy/common/error.h"
#include "canopy/common/interrupt.h"
#include "canopy/common/value_text.h"
#include "canopy/datasets/frame_sequence.h"
#include "canopy/jobs/map_job.h"
#include "canopy/jobs/mcap_frames.h"
#include "canopy/jobs/recorded_map_job.h"
#include "canopy/mapping/frame_mapping.h"
#include "cli_util.h"
#include "commands.h"

namespace canopy::cli {

namespace {

struct MapOptions {
  std::string world = default_world_path();
  std::string views = "ring";
  std::string config = settings::default_settings_path();
  std::string seg;
  double pgt = -1.0;
  std::string out;
  std::string frames, intrinsics, label_colors;
  std::string export_dir;
  bool no_report = false;
  double max_dt_s = datasets::FrameReaderOptions{}.max_time_diff_s;
  std::string mcap;                // a ROS 2 recording instead of a world
  jobs::McapFrameOptions mcap_options;
};

// Maps a recorded sequence into --out with a line per frame (jobs::map_recorded).
void map_sequence(const jobs::RecordedSequence& seq, const MapOptions& opt, const settings::Settings& bundle) {
  jobs::RecordedMapParams job;
  job.settings = bundle;
  job.out = opt.out;
  job.on_frame = [](const mapping::FrameMapStep& s) {
    if (s.mapped)
      std::fprintf(stderr, "frame %s: %zu points, insert %.1f ms\n", s.name.c_str(), s.extract.points, s.insert.ms_total);
    else
      std::fprintf(stderr, "frame %s: skipped (%s)\n", s.name.c_str(), s.skip_reason.c_str());
  };
  job.stop_requested = [] { return interrupt_requested(); };
  const jobs::RecordedMapResult r = jobs::map_recorded(seq, job);
  std::printf("mapped %zu frames (%zu skipped): %zu occupied voxels; wrote %s\n", r.mapped, r.skipped,
              r.occupied_voxels, opt.out.c_str());
}

// canopy map --frames: no world, no ground truth; the map and what each frame gave
// (jobs::map_recorded, canopy/jobs/recorded_map_job.h).
void map_recorded(const MapOptions& opt, const settings::Settings& bundle) {
  datasets::FrameReaderOptions reader;
  reader.intrinsics_file = opt.intrinsics;
  reader.label_colors_file = opt.label_colors;
  reader.max_time_diff_s = opt.max_dt_s;
  reader.label_images = bundle.mapping.extractor.source == perception::LabelSource::kTruth;
  const datasets::FrameSequence frames = datasets::FrameSequence::open(opt.frames, reader);
  const jobs::RecordedSequence seq = jobs::frames_sequence(frames, reader);
  spdlog::info("mapping {} frames ({} layout, {} skipped while pairing), labels {}: {}", frames.size(),
               datasets::to_string(frames.layout()), frames.skipped().size(), reader.label_images ? "from images" : "color",
               opt.pgt < 0.0 ? "no simulated mask noise (p_gt 1; --pgt adds it)"
                             : "simulated mask noise, p_gt " + format_number(bundle.mapping.extractor.p_gt, "%g"));
  for (const std::string& note : frames.notes()) spdlog::warn("{}: {}", opt.frames, note);
  map_sequence(seq, opt, bundle);
}

// canopy map --mcap: a ROS 2 recording (jobs::McapFrames, canopy/jobs/mcap_frames.h) mapped
// as --frames maps a folder.
void map_mcap(const MapOptions& opt, const settings::Settings& bundle) {
  jobs::McapFrameOptions o = opt.mcap_options;
  o.max_dt_s = opt.max_dt_s;
  o.label_images = bundle.mapping.extractor.source == perception::LabelSource::kTruth;
  jobs::McapFrames recording(opt.mcap, o);
  for (const std::string& line : recording.choices()) spdlog::info("{}: {}", opt.mcap, line);
  const jobs::McapFrameOptions& used = recording.options();
  const jobs::RecordedSequence seq = recording.sequence();
  spdlog::info("mapping {} frames of {} ({} skipped while pairing), camera frame {} in {}, labels {}: {}", seq.size,
               opt.mcap, seq.skipped.size(), used.frame, used.world_frame, o.label_images ? "from images" : "color",
               opt.pgt < 0.0 ? "no simulated mask noise (p_gt 1; --pgt adds it)"
                             : "simulated mask noise, p_gt " + format_number(bundle.mapping.extractor.p_gt, "%g"));
  for (const std::string& note : seq.notes) spdlog::warn("{}: {}", opt.mcap, note);
  map_sequence(seq, opt, bundle);
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
  auto* mcap = sub->add_option("--mcap", opt->mcap,
                               "Map a ROS 2 recording (MCAP, e.g. what ros2 bag record writes) instead of a world "
                               "(docs/ros2.md)");
  mcap->excludes(world)->excludes(views)->excludes(frames);
  jobs::McapFrameOptions& mo = opt->mcap_options;
  sub->add_option("--rgb", mo.rgb,
                  "--mcap: colour image topic (default: /canopy/wrist/rgb, else the one rgb8/bgr8/rgba8/bgra8 or PNG "
                  "topic, a /color/ or /rgb/ one among several)")
      ->needs(mcap);
  sub->add_option("--depth", mo.depth,
                  "--mcap: depth image topic, registered to the colour camera (default: /canopy/wrist/depth, else the "
                  "one 16UC1/mono16/32FC1 topic, an aligned or registered one among several)")
      ->needs(mcap);
  sub->add_option("--camera-info", mo.camera_info,
                  "--mcap: CameraInfo topic (default: camera_info beside the colour topic, else the only one)")
      ->needs(mcap);
  sub->add_option("--labels", mo.labels, "--mcap with --seg truth: mono8 class-index topic (default: /canopy/wrist/labels)")
      ->needs(mcap);
  sub->add_option("--frame", mo.frame, "--mcap: the depth images' optical frame (default: their header.frame_id)")
      ->needs(mcap);
  sub->add_option("--world-frame", mo.world_frame,
                  "--mcap: the map's frame (default: the root of the camera's /tf tree)")
      ->needs(mcap);
  sub->add_option("--min-range", mo.min_range_m, "--mcap: depths below this are invalid [m]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber)
      ->needs(mcap);
  sub->add_option("--max-range", mo.max_range_m, "--mcap: depths beyond this are invalid [m]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber)
      ->needs(mcap);
  sub->add_option("--intrinsics", opt->intrinsics, "--frames, TUM: camera YAML (default: DIR/camera.yaml)")
      ->needs(frames);
  sub->add_option("--label-colors", opt->label_colors,
                  "--frames with --seg truth: class-colour table of the label images (YAML; default: the "
                  "classes' drawing colours)")
      ->needs(frames);
  sub->add_option("--max-dt", opt->max_dt_s,
                  "--frames (TUM) and --mcap: largest RGB-depth and depth-pose time difference [s]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_option("--seg", opt->seg, "Labels: color (HSV segmentation) or truth (renderer; with --frames: the label images); default from config")
      ->check(CLI::IsMember({"color", "truth"}));
  sub->add_option("--pgt", opt->pgt,
                  "Simulated mask noise: probability a mask keeps its class (1 = no noise); default: the config's "
                  "mapping.extractor.p_gt, with --frames 1 (recorded labels are taken as they are)")
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--out", opt->out, "Output folder")->required();
  sub->add_option("--export", opt->export_dir,
                  "Also write a NeRF / Gaussian-splatting dataset (nerfstudio layout) of the views, with held-out "
                  "ring views, into this folder")
      ->excludes(frames)
      ->excludes(mcap);
  sub->add_flag("--no-report", opt->no_report, "Skip report.html (the interactive 3D report, docs/report.md; world views only)");
  sub->callback([opt] {
    // Ctrl-C and SIGTERM: the views mapped so far are saved, marked incomplete.
    const InterruptScope interrupts;
    settings::Settings bundle = load_settings(opt->config);
    if (!opt->seg.empty()) bundle.set("mapping.extractor.source", opt->seg, "--seg");
    if (opt->pgt >= 0.0) bundle.set("mapping.extractor.p_gt", format_number(opt->pgt, NumberFormat::kDigits17), "--pgt");
    // A recording's labels (or its colours' segmentation) are what they are: the bundle's p_gt
    // is the simulator's mask noise, applied to recorded frames only when --pgt asks for it.
    else if (!opt->frames.empty()) bundle.set("mapping.extractor.p_gt", "1", "--frames");
    else if (!opt->mcap.empty()) bundle.set("mapping.extractor.p_gt", "1", "--mcap");
    if (!opt->frames.empty()) return map_recorded(*opt, bundle);
    if (!opt->mcap.empty()) return map_mcap(*opt, bundle);
    jobs::MapJobParams job;
    job.world_file = opt->world;
    job.views = opt->views;
    job.settings = bundle;
    job.out = opt->out;
    job.export_dir = opt->export_dir;
    job.report = !opt->no_report;
    job.stop_requested = [] { return interrupt_requested(); };
    job.on_view = [](const jobs::MapViewStep& s) {
      std::fprintf(stderr,
                   "view %zu/%zu: %zu points, insert %.1f ms, coverage %.3f, fruit entropy %.1f, %zu occupied "
                   "voxels\n",
                   s.view + 1, s.views, s.points, s.ms_insert, s.coverage, s.total_entropy, s.occupied_voxels);
    };
    const jobs::MapJobResult r = jobs::map_views(job);
    if (r.dataset_written)
      std::printf("wrote %s (nerfstudio dataset: %zu training views, %zu held-out views)\n", opt->export_dir.c_str(),
                  r.dataset_train, r.dataset_test);
    std::printf("mapped %zu views: coverage %.3f, fruit entropy %.1f, %.1f ms per insertion; wrote %s\n", r.views,
                r.coverage, r.total_entropy, r.ms_per_insertion, opt->out.c_str());
  });
}

}  // namespace canopy::cli
