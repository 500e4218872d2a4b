#pragma once
// Job: map a list of views of a world. What `canopy map --world` does: render each view with
// a free camera, label and insert it into the semantic map, score the map against the truth,
// and after every view save the map (map.csm, map.ply, map.bt) and metrics.json (with the
// history of every view so far); optionally a nerfstudio dataset of the views.

#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <string>

#include "canopy/mapping/scan_inserter.h"
#include "canopy/settings/settings.h"
#include "canopy/perception/semantic_extractor.h"

namespace canopy::jobs {

/// A frame's insertion statistics under the keys of metrics.json and Python's Map.insert:
/// points, skipped_bad_depth, skipped_out_of_range, carved_missing_depth, skipped_bad_label,
/// skipped_bad_point, masks, masks_flipped, hit_voxels, free_voxels, saturated_updates,
/// ms_insert, ms_filter, ms_raycast, ms_update.
nlohmann::json insert_stats_json(const mapping::InsertStats& insert, const perception::ExtractStats& extract);

/// What one mapped view gave (the CLI prints a line of it).
struct MapViewStep {
  std::size_t view = 0, views = 0;   ///< 0-based index, and the number of views.
  std::size_t points = 0;
  double ms_insert = 0.0;
  double coverage = 0.0, total_entropy = 0.0;
  std::size_t occupied_voxels = 0;
};

/// What map_views needs.
struct MapJobParams {
  std::string world_file;            ///< Loaded and checked by the world job.
  std::string views = "ring";        ///< 'ring', 'aisle' or a file of 'x y z qw qx qy qz' lines.
  settings::Settings settings;        ///< Mapping section used; saved as settings.yaml.
  std::string out;                   ///< Output folder.
  std::string export_dir;            ///< nerfstudio dataset folder; "" exports none.
  bool report = true;                ///< Write report.html into the folder at the end (run_report.h).
  std::function<void(const MapViewStep&)> on_view;  ///< After each view's files are written.
  std::function<bool()> stop_requested;              ///< Polled before each view.
};

/// What it did.
struct MapJobResult {
  std::size_t views = 0;
  double coverage = 0.0, total_entropy = 0.0;   ///< After the last view.
  double ms_per_insertion = 0.0;
  bool dataset_written = false;
  std::size_t dataset_train = 0, dataset_test = 0;
};

/// Maps the views and publishes the folder (and the export). A stop request before the first
/// view writes nothing, after it publishes the views so far (metrics.json "complete": false);
/// both throw Interrupted.
MapJobResult map_views(const MapJobParams& params);

}  // namespace canopy::jobs
