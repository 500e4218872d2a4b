#include "canopy/jobs/recorded_map_job.h"

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"
#include "canopy/common/io.h"
#include "canopy/common/params.h"
#include "canopy/datasets/sequence_mapping.h"
#include "canopy/jobs/map_job.h"
#include "canopy/mapping/map_io.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/perception/semantic_extractor.h"

namespace canopy::jobs {

RecordedMapResult map_recorded(const RecordedSequence& frames, const RecordedMapParams& p) {
  const mission::MappingSettings& cfg = p.settings.mapping;
  StagedDir out(p.out, "map", StagedDir::Mode::kReplace, p.out_option);
  mapping::SemanticOcTree map(cfg.map, frames.classes);
  mapping::ScanInserter inserter(map);
  perception::SemanticExtractor extractor(cfg.extractor, frames.classes);
  write_file_atomic(out.path("settings.yaml"), p.settings.to_yaml_text());
  write_file_atomic(out.path("run.yaml"), yaml_text(frames.run));

  datasets::SequenceMapResult seq = datasets::map_frames(frames.size, frames.read, frames.name, frames.skipped,
                                                         extractor, inserter, p.on_frame, p.stop_requested);
  const std::vector<mapping::FrameMapStep>& steps = seq.steps;
  const std::vector<datasets::SkippedFrame>& skipped = seq.skipped;
  RecordedMapResult r;
  r.complete = seq.complete;
  r.mapped = seq.mapped;
  r.skipped = skipped.size();
  if (!r.complete && r.mapped == 0) throw Interrupted("interrupted before the first frame; nothing was written");
  if (r.mapped == 0)
    throw InputError(frames.source + ": no frame could be mapped (" + std::to_string(skipped.size()) + " skipped)");
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
  write_json_atomic(out.path("frames.json"), {{"complete", r.complete},
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
