#pragma once
// Job: run a mission with its video, dataset export and run folder. What `canopy mission`,
// `canopy run` and Python's canopy.run_mission do around mission::Mission: the video options
// checked and the VideoWriter wired to the mission, the nerfstudio export fed with its views,
// the run folder (views.csv, summary.json, map, report.html, plots) written and published.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "canopy/mapping/semantic_octree.h"
#include "canopy/mission/mission.h"
#include "canopy/settings/mission_params.h"
#include "canopy/settings/settings.h"
#include "canopy/robot/robot_config.h"
#include "canopy/world/world.h"

namespace canopy::jobs {

/// The mission's video: an MP4 of the chase view with the wrist and map insets.
struct VideoOptions {
  std::string path;       ///< "" records no video.
  int width_px = 640;
  int height_px = 480;
  double fps = 25.0;      ///< Frames per simulated second.
};

/// What the video options were called where they were given (the CLI's flags, Python's
/// keywords), so that messages name them.
struct VideoOptionNames {
  std::string path = "--video";
  std::string size = "--video-size";
  std::string fps = "--video-fps";
};

/// Parses a video frame size "WxH" and checks the options (even sizes in [64, 1920] x
/// [64, 1080], fps in (0, 120], a writable path, VideoWriter::validate_output_path); throws
/// InputError naming the option. An empty `path` gives no video and checks nothing.
VideoOptions video_options(const std::string& path, const std::string& size, double fps,
                           const VideoOptionNames& names = {});

/// What run_mission_job needs besides the world.
struct MissionJobParams {
  std::string world_file;             ///< The world file as given (the summary names it).
  settings::Settings settings;         ///< The bundle the mission runs with (method included).
  std::uint64_t seed = 1;             ///< Seeds segmentation noise, the planner's draws and OMPL.
  std::string out;                    ///< Run folder; "" writes none (the summary is still made).
  std::string out_option = "--out";   ///< The name of `out` in messages.
  VideoOptions video;                 ///< video_options' result; path "" records none.
  std::string export_dir;             ///< nerfstudio dataset folder; "" exports none.
  bool plots = false;                 ///< Draw sc_entropy.svg and runtime.svg into the run folder (figures.h).
  bool report = true;                 ///< Write report.html into the run folder (run_report.h).
  bool keep_map = false;              ///< Return a copy of the final map.
  bool strict_colours = false;        ///< A non-fruit material coloured like fruit is an error (check_world_colours).
  /// Called after every successful view (after the video's and the export's hooks) with its
  /// frame, the simulator in that state and the mission's map with the view inserted (Python's
  /// on_view: a ROS bag of the run). It changes no result.
  std::function<void(const records::ViewRecord&, const LabelledFrame&, const sim::Simulator&,
                     const mapping::SemanticOcTree&)> on_view;
};

/// What a mission job did.
struct MissionJobResult {
  records::MissionResult result;
  nlohmann::json summary;                        ///< summary.json (written or not).
  std::string video_error;                       ///< Why the video is missing; "" when it is written (or none asked).
  std::size_t video_frames = 0;
  bool report_written = false;                   ///< report.html is in the run folder.
  bool plots_interrupted = false;                ///< A signal after the mission's end: published without its plots.
  bool dataset_written = false;                  ///< The export was published (complete missions only).
  std::size_t dataset_train = 0, dataset_test = 0;  ///< Its training and held-out views.
  std::shared_ptr<mapping::SemanticOcTree> map;  ///< The final map, when keep_map.
};

/// Throws InputError (naming the setting) unless the base can stand at every stop of `stops`
/// in `spec` (the arm over the stop's x) and at its y, within its joints' ranges (the URDF's).
void check_stops_in_reach(const world::WorldSpec& spec, const settings::StopParams& stops,
                          const RobotConfig& robot = default_robot_config());

/// Checks the places a mission writes before any work (InputError): --out, --export and
/// --video are never inside one another nor inside another command's output folder (a later
/// commit would delete them), and --out is not a symbolic link. run_mission_job calls it too.
void check_mission_outputs(const MissionJobParams& params);

/// Runs the closed-loop mission on `world` (checked against the settings' labels first,
/// check_world_colours) with `callbacks` (progress, stop requests, a tick: the job adds the
/// video's and the export's hooks, and with a video the caller's video_tick runs after the
/// video's, at its frame rate; params.on_view is the caller's view hook), records the video,
/// writes the export and the run folder, and publishes both. `amend` may change the result before it is written (Python notes a Ctrl-C the last
/// poll missed). A stop request before the mission starts is an Interrupted error and writes
/// nothing; a video whose encoder failed is reported in video_error, and the rest is written.
MissionJobResult run_mission_job(const world::World& world, const MissionJobParams& params,
                                 mission::MissionCallbacks callbacks = {},
                                 const std::function<void(records::MissionResult&)>& amend = {});

}  // namespace canopy::jobs
