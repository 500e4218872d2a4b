#pragma once
// Job: report.html, the interactive report of a run folder (docs/report.md). One HTML file,
// opened from file:// with no server and no network: three.js (Debian's libjs-three) and the
// page's script (web/report.js in the data folder) are inlined, the run's data is a JSON block,
// and the wrist thumbnails are PNG contact sheets beside it (report_rgb_<i>.png,
// report_labels_<i>.png). The map states after each view come from the run's MapReplay.
//
// The file is the same bytes for the same run, except one line, the run's wall times
// (`<script id="canopy-wall">`), which no two runs share.

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/mission/mission.h"
#include "canopy/records/replay.h"
#include "canopy/robot/robot_description.h"
#include "canopy/settings/settings.h"
#include "canopy/world/world.h"

namespace canopy::jobs {

/// Size limits of a report (docs/report.md#bounds).
struct ReportBounds {
  std::size_t max_voxels = 250000;    ///< Voxels drawn; beyond, every m-th (in order of first sight).
  std::size_t max_changes = 500000;   ///< Voxel changes kept; beyond, map states every m views.
  std::size_t max_thumbs = 240;       ///< Thumbnails kept; beyond, every m-th view's.
  int thumbs_per_sheet = 100;         ///< Thumbnails per PNG sheet (10 per row).
};

/// What report.html holds besides the replay: the run as a JSON object (mission_report_data,
/// map_report_data).
struct RunReport {
  nlohmann::json data;
  nlohmann::json wall;  ///< Wall times (the line that differs between equal runs).
  /// The robot's shapes by link (robot_shapes_json), drawn at each view's link poses when the
  /// replay recorded them; null: the links' frames only.
  nlohmann::json robot_shapes;
};

/// A mission's report data: views (poses, phases, failures, gains, curves), stops, fruits,
/// settings that differ from the defaults, final metrics, failures by cause, times.
RunReport mission_report_data(const records::MissionResult& result, const settings::Settings& settings,
                              const world::World& world, const nlohmann::json& summary);

/// A `canopy map` folder's report data: the views' poses and curves (metrics.json's history).
RunReport map_report_data(const nlohmann::json& metrics, const std::vector<Pose>& views,
                          const settings::Settings& settings, const world::World& world);

/// The robot's geometry for the page: by link name, the link's visual shapes (its collision
/// shapes when it has no visual), each {type: box | sphere | cylinder | capsule, size (box's
/// edges) or radius and length (along the shape's z), pose in the link frame as x y z qw qx qy
/// qz, rgba}. Meshes are left out (the URDF's robot has none).
nlohmann::json robot_shapes_json(const robot::RobotDescription& robot);

/// The settings that differ from the defaults: [{key, value, default}].
nlohmann::json changed_settings(const settings::Settings& settings);

/// Writes report.html and its thumbnail sheets into `dir` (atomically, file by file) and
/// returns the files written. Throws IoError when three.js or the page's script is missing
/// (the message names the package or file).
std::vector<std::string> write_run_report(const std::string& dir, RunReport report, const records::MapReplay& replay,
                                          const ReportBounds& bounds = {});

/// The replay packed for the page (what write_run_report embeds): voxel keys and per-state
/// changes in base64; beyond the bounds, every m-th voxel ("voxel_step") and map states every
/// `step` views, with a note saying so.
nlohmann::json pack_replay(const records::MapReplay& replay, const mapping::SemanticMapParams& map,
                           const ReportBounds& bounds);

/// Each fruit of `fruits` (report data: objects with "id", in the order of the metrics' target
/// fruits) gets "views_seen", the successful views that saw it (a pixel of it in the view's true
/// instance image within the camera's range: MapReplay::instances_seen), and "views_raised",
/// those that raised its coverage by more than 0.001; each only when the replay recorded it.
void set_fruit_views(nlohmann::json& fruits, const records::MapReplay& replay);

/// True when Debian's libjs-three is installed (three.js and its orbit controls).
bool report_libraries_present();

/// The inlined scripts of a page: three.js and its orbit controls (with `three_js`; a page that
/// draws SVG only goes without their 0.85 MB), the charts' axes (web/report_axes.js) and the
/// page script. Throws IoError naming what is missing.
std::string report_scripts(const std::string& page_script, bool three_js = true);

/// The page around a data block: `title`, the scripts, the JSON data and the wall line.
std::string report_page(const std::string& title, const std::string& scripts, const nlohmann::json& data,
                        const nlohmann::json& wall, const std::string& css);

}  // namespace canopy::jobs
