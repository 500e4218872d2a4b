#pragma once
// What a run records so that its report (jobs/run_report.h) can replay it without running it
// again: after each successful view, the voxels whose drawn state changed (occupied or not,
// most likely class, occupancy and entropy in a few levels), each fruit's coverage, a
// thumbnail of the wrist RGB, of its true labels and of the labels mapped (after noise), and
// the robot's link poses at the view, and the fruit instances the view saw.
//
// The mission feeds it from its scan pipeline's thread (record_scan, record_fruits) and from
// its own (record_frame); `canopy map` from its loop. Scans are recorded in the order they
// were taken; scan k is successful view k.

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "canopy/common/classes.h"
#include "canopy/common/frame.h"
#include "canopy/common/timer.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/mapping/semantic_octree.h"

namespace canopy::records {

/// The drawn state of a voxel in one 16-bit word; 0 = not drawn (free or unknown).
/// Bit 15 set for an occupied voxel; bits 0-5 its most likely class, 6-7 its occupancy
/// probability in 4 levels over (0.5, 1], 8-10 its entropy in 8 levels over [0, ln K].
std::uint16_t drawn_state(const mapping::SemanticOcTree& map, const mapping::SemanticState* s);

/// One change of a voxel's drawn state.
struct VoxelChange {
  std::uint32_t voxel = 0;  ///< Index into MapReplay::voxels.
  std::uint16_t state = 0;  ///< drawn_state after the scan.
};

/// A run's record for its report.
class MapReplay {
 public:
  /// Thumbnails are `thumb_width_px` wide (the frame's aspect kept).
  explicit MapReplay(SemanticClasses classes, int thumb_width_px = 128);

  /// After a scan's insertion: the drawn state of every voxel it updated (`updates`,
  /// ScanInserter::last_updates) compared with the last one recorded. With `occupancy`
  /// (ScanInserter::last_occupancy), voxels free before and after the scan are skipped unread.
  void record_scan(const mapping::SemanticOcTree& map, const std::vector<mapping::VoxelUpdate>& updates,
                   const std::vector<std::uint8_t>* occupancy = nullptr);
  /// The coverage of each target fruit after the last scan (under the metrics' rule).
  void record_fruits(const evaluation::MapMetrics& metrics);
  /// The frame of the next successful view (its thumbnails and the fruit instances it saw) and,
  /// when given, the labels that were mapped from it (the extractor's, after segmentation and
  /// noise; the frame's size).
  void record_frame(const LabelledFrame& frame, const Image<std::uint8_t>* mapped_labels = nullptr);
  /// The robot's links at the next successful view: their names and parents (taken from the
  /// first call) and their world poses.
  void record_robot(const std::vector<std::string>& links, const std::vector<std::string>& parents,
                    const std::vector<Pose>& T_world_link);

  /// Voxel keys in the order they were first drawn.
  const std::vector<octomap::OcTreeKey>& voxels() const { return voxels_; }
  /// Per scan, its changes in voxel order.
  const std::vector<std::vector<VoxelChange>>& scans() const { return scans_; }
  /// Per scan, each target fruit's coverage (empty scans when the metrics were off).
  const std::vector<std::vector<double>>& fruit_coverage() const { return fruits_; }
  /// Scan `scan`'s fruit coverage once the pipeline has recorded it (a copy, safe while the
  /// pipeline records the next: what a recording of the running mission reads); nullopt before.
  std::optional<std::vector<double>> fruit_coverage_after(std::size_t scan) const;
  /// Per recorded frame, the RGB and label thumbnails.
  const std::vector<Image<Rgb8>>& rgb() const { return rgb_; }
  const std::vector<Image<Rgb8>>& labels() const { return labels_; }
  /// Per recorded frame, the thumbnail of the labels mapped (empty when none were given).
  const std::vector<Image<Rgb8>>& mapped_labels() const { return mapped_; }
  /// Per recorded frame, the fruit instances it saw, ascending: the ids of its true instance
  /// image whose pixels hold a depth (within the camera's range; every pixel of the instance
  /// image when the depth image is of another size). Occlusion is the renderer's.
  const std::vector<std::vector<int>>& instances_seen() const { return seen_; }
  /// The robot's links, their parents, and per recorded view their world poses (empty without).
  const std::vector<std::string>& robot_links() const { return robot_links_; }
  const std::vector<std::string>& robot_parents() const { return robot_parents_; }
  const std::vector<std::vector<Pose>>& robot_poses() const { return robot_poses_; }
  const SemanticClasses& classes() const { return classes_; }
  /// Number of changes over all scans.
  std::size_t change_count() const;
  /// Wall time spent recording so far [s] (scans on the pipeline's thread, frames on the mission's).
  double seconds() const;

 private:
  SemanticClasses classes_;
  int thumb_width_px_;
  std::vector<octomap::OcTreeKey> voxels_;
  std::unordered_map<std::uint64_t, std::pair<std::uint32_t, std::uint16_t>> last_;  // code -> voxel, state
  std::vector<std::vector<VoxelChange>> scans_;
  std::vector<std::vector<double>> fruits_;
  std::vector<Image<Rgb8>> rgb_, labels_, mapped_;
  std::vector<std::vector<int>> seen_;
  std::vector<std::string> robot_links_, robot_parents_;
  std::vector<std::vector<Pose>> robot_poses_;
  double scan_seconds_ = 0.0, frame_seconds_ = 0.0;
  // Scans come from the pipeline's thread, frames from the mission's: one lock each, so that
  // neither waits for the other.
  mutable std::mutex scan_mutex_, frame_mutex_;
};

}  // namespace canopy::records
