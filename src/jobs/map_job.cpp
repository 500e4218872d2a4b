#include "canopy/jobs/map_job.h"


#include <spdlog/spdlog.h>

#include <memory>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/value_text.h"
#include "canopy/common/timer.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/jobs/run_report.h"
#include "canopy/jobs/world_job.h"
#include "canopy/mapping/frame_mapping.h"
#include "canopy/mapping/map_io.h"
#include "canopy/datasets/nerfstudio.h"
#include "canopy/jobs/test_views.h"
#include "canopy/records/view_columns.h"
#include "canopy/sim/renderer.h"

namespace canopy::jobs {

nlohmann::json insert_stats_json(const mapping::InsertStats& s, const perception::ExtractStats& e) {
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

namespace {

// A view's entry of metrics.json's history.
nlohmann::json history_step(std::size_t i, const Pose& T, double ms_render, const mapping::FrameMapStep& fs,
                            const evaluation::MapMetrics& m) {
  nlohmann::json step = records::map_history_metrics(m);  // the view columns' map figures
  step.update({{"view", i}, {"pose", pose_to_json(T)}, {"ms_render", ms_render},
               {"insert", insert_stats_json(fs.insert, fs.extract)}});
  return step;
}

}  // namespace

MapJobResult map_views(const MapJobParams& p) {
  const settings::MappingSettings& cfg = p.settings.mapping;
  check_disjoint_outputs({{p.out, "--out"}, {p.export_dir, "--export"}});
  const world::WorldSpec spec = load_world_spec(p.world_file);
  const world::World world = build_world(spec);
  check_world_colours(world, cfg.extractor);
  const std::vector<Pose> views = evaluation::views_from_spec(p.views, world);
  StagedDir out(p.out, "map");
  std::unique_ptr<StagedDir> export_out;
  std::unique_ptr<datasets::DatasetExport> dataset;
  if (!p.export_dir.empty()) {
    export_out = std::make_unique<StagedDir>(p.export_dir, "dataset", StagedDir::Mode::kReplace, "--export");
    dataset = std::make_unique<datasets::DatasetExport>(export_out->working_dir(), spec.classes, spec.camera);
  }

  sim::Simulator sim(world, default_robot_config());
  sim::Renderer renderer(sim, spec.camera);
  mapping::SemanticOcTree map(cfg.map, spec.classes);
  mapping::ScanInserter inserter(map);
  perception::SemanticExtractor extractor(cfg.extractor, spec.classes);
  write_file_atomic(out.path("settings.yaml"), p.settings.to_yaml_text());  // a loadable --config
  YAML::Node run = run_record("map", spec);
  run["views"] = p.views;
  nlohmann::json poses = nlohmann::json::array();
  for (const Pose& T : views) poses.push_back(pose_to_json(T));
  run["view_poses"] = YAML::Load(poses.dump());
  write_file_atomic(out.path("run.yaml"), yaml_text(run));
  spdlog::info("mapping {} views ({}), labels {}, P_gt {}", views.size(), p.views,
               perception::to_string(cfg.extractor.source), cfg.extractor.p_gt);

  // What the report replays (replay.h).
  std::unique_ptr<records::MapReplay> replay;
  if (p.report && report_libraries_present()) replay = std::make_unique<records::MapReplay>(spec.classes);
  else if (p.report) spdlog::warn("report.html skipped (needs Debian's libjs-three; run tools/deps.sh)");
  auto write_report = [&](const nlohmann::json& metrics) {
    if (replay) write_run_report(out.working_dir(), map_report_data(metrics, views, p.settings, world), *replay);
  };
  nlohmann::json history = nlohmann::json::array();
  double insert_ms_sum = 0.0;
  nlohmann::json last;
  std::size_t done = 0;
  for (std::size_t i = 0; i < views.size(); ++i) {
    if (p.stop_requested && p.stop_requested()) break;
    const Stopwatch render_watch;
    const LabelledFrame frame = renderer.render_free_camera(views[i]);
    const double ms_render = render_watch.ms();
    Image<std::uint8_t> mapped_labels;  // what the extractor labelled (after noise), for the report
    const mapping::FrameMapStep fs = mapping::map_frame(frame, extractor, inserter, replay ? &mapped_labels : nullptr);
    if (dataset) dataset->add_train(frame);
    insert_ms_sum += fs.insert.ms_total;
    const evaluation::MapMetrics m = evaluation::evaluate_map(map, world.truth, cfg.metrics);
    if (replay) {
      replay->record_scan(map, inserter.last_updates(), &inserter.last_occupancy());
      replay->record_fruits(m);
      replay->record_frame(frame, &mapped_labels);
    }
    mapping::save_map(map, out.path("map.csm"));
    const std::size_t occupied = mapping::export_ply(map, out.path("map.ply"));
    mapping::export_bt(map, out.path("map.bt"));

    history.push_back(history_step(i, views[i], ms_render, fs, m));
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
    if (p.on_view) p.on_view({i, views.size(), fs.extract.points, fs.insert.ms_total, m.coverage, m.total_entropy, occupied});
  }
  if (done == 0) throw Interrupted("interrupted before the first view; nothing was written");
  if (done < views.size()) {  // interrupted: what is mapped is saved, marked incomplete
    last["complete"] = false;
    write_json_atomic(out.path("metrics.json"), last);
    write_report(last);
    out.commit();
    throw Interrupted("interrupted after " + std::to_string(done) + " of " + std::to_string(views.size()) +
                      " views; the map so far is saved in " + p.out + " (metrics.json \"complete\": false)");
  }
  MapJobResult r;
  if (dataset) {
    render_test_views(*dataset, sim, world, default_test_ring());
    dataset->finish({{"command", "map"}, {"world", p.world_file}, {"views", p.views}});
    export_out->commit();
    r.dataset_written = true;
    r.dataset_train = dataset->train_count();
    r.dataset_test = dataset->test_count();
  }
  write_report(last);
  out.commit();
  r.views = views.size();
  r.coverage = history.back()["coverage"].get<double>();
  r.total_entropy = history.back()["total_entropy"].get<double>();
  r.ms_per_insertion = insert_ms_sum / double(views.size());
  return r;
}

}  // namespace canopy::jobs
