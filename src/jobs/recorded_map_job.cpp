#include "canopy/jobs/recorded_map_job.h"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <optional>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/params.h"
#include "canopy/datasets/sequence_mapping.h"
#include "canopy/jobs/map_job.h"
#include "canopy/mapping/map_io.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/perception/semantic_extractor.h"

namespace canopy::jobs {

namespace {
// A map is anchored away from its frame's origin when the first frame lies beyond this share
// of the octree's half extent: the data then has the rest of the keys on every side.
constexpr double kAnchorFraction = 0.25;
double map_half_extent_m(double resolution) { return 32768.0 * resolution; }  // 16-bit keys
}  // namespace

RecordedSequence frames_sequence(const datasets::FrameSequence& frames, const datasets::FrameReaderOptions& reader) {
  RecordedSequence seq;
  seq.source = frames.dir();
  seq.classes = frames.classes();
  seq.size = frames.size();
  seq.name = [&frames](std::size_t i) { return frames.name(i); };
  seq.read = [&frames](std::size_t i, LabelledFrame* f, std::string* why) { return frames.read(i, f, why); };
  seq.skipped = frames.skipped();
  seq.notes = frames.notes();
  seq.run["command"] = "map";
  seq.run["frames"] = frames.dir();
  seq.run["layout"] = datasets::to_string(frames.layout());
  seq.run["labels"] = reader.label_images ? "label images" : "color";
  seq.run["classes"] = frames.classes().names;
  seq.run["max_time_diff_s"] = reader.max_time_diff_s;
  return seq;
}

RecordedMapResult map_recorded(const RecordedSequence& frames, const RecordedMapParams& p) {
  const settings::MappingSettings& cfg = p.settings.mapping;
  StagedDir out(p.out, "map", StagedDir::Mode::kReplace, p.out_option);
  mapping::SemanticOcTree map(cfg.map, frames.classes);
  mapping::ScanInserter inserter(map);
  perception::SemanticExtractor extractor(cfg.extractor, frames.classes);
  write_file_atomic(out.path("settings.yaml"), p.settings.to_yaml_text());
  YAML::Node run = YAML::Clone(frames.run);
  if (!run["p_gt"]) run["p_gt"] = cfg.extractor.p_gt;  // the mask noise the frames were mapped with
  write_file_atomic(out.path("run.yaml"), yaml_text(run));

  // A recording far from its frame's origin (a farm's map frame, UTM) would fall outside the
  // octree's keys (+-32768 voxels: +-491.5 m at 0.015 m) and map nothing: its map is anchored
  // at the first frame's camera (whole voxels), and frames.json says where.
  const double resolution = map.getResolution();
  const double anchor_beyond_m = kAnchorFraction * map_half_extent_m(resolution);
  std::optional<Vec3> anchor;
  const auto read = [&](std::size_t i, LabelledFrame* f, std::string* why) {
    if (!frames.read(i, f, why)) return false;
    if (!anchor) {
      const Vec3 at = f->T_world_camera.translation();
      anchor = at.norm() > anchor_beyond_m ? Vec3((at / resolution).array().round() * resolution) : Vec3::Zero();
      if (!anchor->isZero())
        spdlog::info("the first frame's camera is {:.1f} m from its frame's origin (beyond {:.0f} m): the map's "
                     "origin is put at [{:.3f}, {:.3f}, {:.3f}] m in that frame (frames.json map_origin_m)",
                     at.norm(), anchor_beyond_m, anchor->x(), anchor->y(), anchor->z());
    }
    f->T_world_camera.pretranslate(-*anchor);
    return true;
  };
  datasets::SequenceMapResult seq = datasets::map_frames(frames.size, read, frames.name, frames.skipped, extractor,
                                                         inserter, p.on_frame, p.stop_requested);
  const std::vector<mapping::FrameMapStep>& steps = seq.steps;
  const std::vector<datasets::SkippedFrame>& skipped = seq.skipped;
  RecordedMapResult r;
  r.complete = seq.complete;
  r.mapped = seq.mapped;
  r.skipped = skipped.size();
  if (!r.complete && r.mapped == 0) throw Interrupted("interrupted before the first frame; nothing was written");
  if (r.mapped == 0)
    throw InputError(frames.source + ": no frame could be mapped (" + std::to_string(skipped.size()) + " skipped)");
  mapping::InsertStats total;
  for (const mapping::FrameMapStep& s : steps) {
    total.points += s.insert.points;
    total.hit_updates += s.insert.hit_updates;
    total.bad_point += s.insert.bad_point;
    total.bad_label += s.insert.bad_label;
    total.outside_map += s.insert.outside_map;
    total.beyond_range += s.insert.beyond_range;
  }
  if (total.hit_updates == 0) {
    const std::string why =
        std::to_string(r.mapped) + " frames mapped, but none put a point in the map (" + std::to_string(total.points) +
        " points: " + std::to_string(total.outside_map) + " outside the map's keys, " +
        std::to_string(total.beyond_range) + " beyond mapping.map.max_range_m, " + std::to_string(total.bad_point) +
        " not finite, " + std::to_string(total.bad_label) + " with an unknown label)";
    if (!r.complete) throw Interrupted("interrupted; " + why + "; nothing was written");
    throw InputError(frames.source + ": " + why + "; nothing was written");
  }
  mapping::save_map(map, out.path("map.csm"));
  r.occupied_voxels = mapping::export_ply(map, out.path("map.ply"));
  mapping::export_bt(map, out.path("map.bt"));
  nlohmann::json steps_json = nlohmann::json::array();
  for (const mapping::FrameMapStep& s : steps) {
    nlohmann::json j = {{"frame", s.name}, {"mapped", s.mapped}};
    if (s.mapped) j["insert"] = insert_stats_json(s.insert, s.extract);
    else j["skip_reason"] = s.skip_reason;
    steps_json.push_back(j);
  }
  nlohmann::json skipped_json = nlohmann::json::array();
  for (const datasets::SkippedFrame& s : skipped) skipped_json.push_back({{"frame", s.name}, {"reason", s.reason}});
  const Vec3 origin = anchor.value_or(Vec3::Zero());
  write_json_atomic(out.path("frames.json"), {{"complete", r.complete},
                                              {"map_origin_m", {origin.x(), origin.y(), origin.z()}},
                                              {"notes", frames.notes},
                                              {"frames_mapped", r.mapped},
                                              {"frames_skipped", skipped.size()},
                                              {"skipped_by_reason", datasets::count_reasons(skipped)},
                                              {"skipped", skipped_json},
                                              {"occupied_voxels", r.occupied_voxels},
                                              {"steps", steps_json}});
  out.commit();
  if (!r.complete)
    throw Interrupted("interrupted after " + std::to_string(r.mapped) + " frames; the map so far is saved in " + p.out +
                      " (frames.json \"complete\": false)");
  return r;
}

}  // namespace canopy::jobs
