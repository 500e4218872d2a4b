#pragma once
// Job: a mission as a ROS 2 recording (MCAP, ros2 profile, CDR; docs/ros2.md). MissionMcap is
// fed by the mission's hooks while it runs (`canopy mission --mcap`, MissionJobParams::mcap):
// nothing is replayed. export_mcap writes a finished run folder's mission (`canopy export-mcap`),
// which a folder can only give by running it again from its own records.
//
// What is written (topics as the ROS 1 bag's, canopy/bag/ros.py): the URDF latched on
// /robot_description, the fixed links once on /tf_static, the moving ones on /tf every
// state_period_s of simulated time and at each view; per successful view the wrist camera's
// rgb8 image, its depth (32FC1 metres with NaN for no return, or 16UC1 millimetres with 0:
// REP 118), true labels (mono8 and in class colours), camera_info, the map's occupied voxels
// (PointCloud2), the views so far as frustums by phase and the fruits by their coverage after
// the view (MarkerArray, from the mission's own per-view metrics). Stamps are an epoch (default: the run's start in wall-clock time) plus
// simulated time, so that a viewer needs no simulated clock.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "canopy/common/frame.h"
#include "canopy/mapping/semantic_octree.h"
#include "canopy/records/records.h"
#include "canopy/records/replay.h"
#include "canopy/ros2/compression.h"
#include "canopy/ros2/mcap_writer.h"
#include "canopy/settings/settings.h"
#include "canopy/sim/simulator.h"
#include "canopy/world/world.h"

namespace canopy::jobs {

/// The topics canopy writes (ROS 1 bags and MCAP alike) and `canopy map --mcap` looks for first.
namespace recording_topics {
constexpr const char* kRgb = "/canopy/wrist/rgb";
constexpr const char* kDepth = "/canopy/wrist/depth";
constexpr const char* kLabels = "/canopy/wrist/labels";
constexpr const char* kLabelsColor = "/canopy/wrist/labels_color";
constexpr const char* kCameraInfo = "/canopy/wrist/camera_info";
constexpr const char* kMap = "/canopy/map";
constexpr const char* kViews = "/canopy/views";
constexpr const char* kFruits = "/canopy/fruits";
constexpr const char* kTf = "/tf";
constexpr const char* kTfStatic = "/tf_static";
constexpr const char* kRobotDescription = "/robot_description";
}  // namespace recording_topics

/// How depth images are written (REP 118).
enum class DepthEncoding {
  k32FC1,  ///< float32 metres, NaN where the camera saw nothing in its range.
  k16UC1,  ///< uint16 millimetres (rounded), 0 where it saw nothing.
};

/// What a mission's MCAP is and how it is written.
struct McapRecordOptions {
  std::string path;                    ///< "" records none.
  std::string option = "--mcap";       ///< Its name in messages.
  ros2::Compression compression = ros2::Compression::kZstd;
  DepthEncoding depth = DepthEncoding::k32FC1;
  /// Stamps are epoch + simulated time [ns since 1970]; nullopt: the run's start in wall-clock time.
  std::optional<std::int64_t> epoch_ns;
  double state_period_s = 0.1;         ///< /tf of the moving links every this much simulated time.
};

/// The words of the command line as McapRecordOptions: a path ending in .mcap (named `option`),
/// compression none|lz4|zstd, depth 32FC1|16UC1, epoch "run" (the run's start), "zero"
/// (simulated time from 1970) or seconds since 1970; InputError naming the flag (`prefix` +
/// "compression", "depth", "epoch") otherwise.
McapRecordOptions mcap_record_options(const std::string& path, const std::string& compression,
                                      const std::string& depth, const std::string& epoch,
                                      const std::string& option = "--mcap", const std::string& prefix = "--mcap-");

/// Now in wall-clock time [ns since 1970].
std::int64_t wall_clock_now_ns();

/// Writes a mission into an MCAP file as it runs. Not thread-safe: the mission's thread calls it.
class MissionMcap {
 public:
  /// Opens the file (its temporary beside it; McapWriter's refusals: InputError).
  MissionMcap(const McapRecordOptions& options, const world::World& world, const settings::Settings& settings);
  ~MissionMcap();
  MissionMcap(const MissionMcap&) = delete;
  MissionMcap& operator=(const MissionMcap&) = delete;

  /// Before the mission's first step: the description, /tf_static, the first /tf and the fruits.
  void start(const sim::Simulator& sim, std::int64_t epoch_ns);
  /// The mission's tick: /tf of the moving links once state_period_s has passed (the first call
  /// starts the recording when start() was not called, at options' epoch or now).
  void state(const sim::Simulator& sim);
  /// After a successful view (the map holds it): its images, camera_info, /tf, map, frustums, fruits.
  void view(const records::ViewRecord& view, const LabelledFrame& frame, const sim::Simulator& sim,
            const mapping::SemanticOcTree& map);
  /// Colours the fruits by the coverage the mission's scan pipeline records in `replay` (its
  /// MissionCallbacks::replay): view k's markers are written once scan k's coverage is recorded,
  /// at the next view or at close(), stamped at view k. Without it the fruits are not coloured.
  void follow_coverage(const records::MapReplay* replay);
  /// Publishes the file; what it holds.
  ros2::McapWriteStats close();
  /// The epoch the stamps count from [ns since 1970].
  std::int64_t epoch_ns() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// What export_mcap writes and from where.
struct ExportMcapParams {
  std::string run_dir;           ///< A `canopy mission` run folder.
  McapRecordOptions mcap;        ///< epoch_ns nullopt: the run's start as its summary.json records it.
  std::function<void(const std::string&)> progress;  ///< The mission's progress lines (may be null).
  std::function<bool()> stop_requested;              ///< Polled while the mission runs (may be null).
};

/// Writes the MCAP of a finished run folder: its mission is run again from its own records
/// (settings.yaml, the world's resolved spec and the seed in summary.json) and recorded as
/// `canopy mission --mcap` does. InputError (and no file) when the folder is not a complete
/// run canopy can replay, or when the replay's views.csv differs from the folder's.
ros2::McapWriteStats export_mcap(const ExportMcapParams& params);

}  // namespace canopy::jobs
