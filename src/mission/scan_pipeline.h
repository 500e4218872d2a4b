#pragma once
// A scan's mapping on a second thread, beside the robot's next move (internal to the mission).
//
// start() inserts a cloud into the map on another thread and then, on the same thread, makes
// the NBV index follow the scan and updates the metrics. follow() waits for the insertion
// and makes the planner's collision environment follow the scan; follow_index() waits for the
// index too; settle() waits for all of it. From start() to settle() the map, the inserter, the
// index and the evaluator belong to the other thread, which only reads the map once the
// insertion is done and the index once it is updated: the caller may read the map after
// follow(), the index after follow_index(), and must not change any of them before settle()
// (but the index after follow_index(): the other thread is past it).
// The environment is the caller's throughout. Every result is the one the same calls in line
// would give.
//
// The other thread lives as long as the pipeline: a thread started anew for each scan cost
// about 2 ms a scan (its stack's first pages, its allocator arena, the task scheduler's
// registration), as much as what overlapping saved.

#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

#include "canopy/common/timer.h"
#include "canopy/evaluation/incremental_evaluator.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/motion/collision.h"
#include "canopy/records/replay.h"
#include "canopy/nbv/voxel_index.h"
#include "canopy/perception/semantic_extractor.h"

namespace canopy::mission {

class ScanPipeline {
 public:
  ScanPipeline(mapping::SemanticOcTree& map, mapping::ScanInserter& inserter, nbv::VoxelIndex& index,
               evaluation::IncrementalEvaluator& evaluator, motion::CollisionEnvironment& environment,
               records::MapReplay* replay = nullptr);
  /// Lets the other thread finish its scan and end (its errors are dropped: they were
  /// reported or are moot).
  ~ScanPipeline();
  ScanPipeline(const ScanPipeline&) = delete;
  ScanPipeline& operator=(const ScanPipeline&) = delete;

  /// Inserts `cloud` and then updates the index (and the metrics when `metrics`) on another
  /// thread. The last scan must be settled.
  void start(perception::LabelledCloud cloud, bool metrics);
  /// A scan was started that the environment does not follow yet (whether or not its
  /// insertion has finished: the answer does not depend on timing).
  bool unfollowed() const { return unfollowed_; }
  /// Waits for the insertion and makes the environment follow the scan (once); rethrows an
  /// error of the insertion.
  void follow();
  /// follow(), then waits for the index (the metrics may still be in the making); rethrows an
  /// error of the index. The caller may then read the index as well as the map.
  void follow_index();
  /// True from start() to settle().
  bool busy() const { return busy_; }
  /// follow(), then waits for the index and the metrics; returns the other thread's times
  /// (insertion and index as mapping, metrics as evaluation).
  PhaseTimes settle();

 private:
  mapping::SemanticOcTree& map_;
  mapping::ScanInserter& inserter_;
  nbv::VoxelIndex& index_;
  evaluation::IncrementalEvaluator& evaluator_;
  motion::CollisionEnvironment& environment_;
  records::MapReplay* replay_;  // records each scan's changes after its metrics (null: none)
  bool unfollowed_ = false, busy_ = false;  // the caller's view

  enum class Stage { kIdle, kQueued, kInserted, kIndexed, kDone };
  void run();  // the other thread
  std::mutex mutex_;
  std::condition_variable changed_;
  Stage stage_ = Stage::kIdle;  // guarded by mutex_, as are the members below
  bool quit_ = false, metrics_ = false;
  perception::LabelledCloud cloud_;
  std::exception_ptr insert_error_, index_error_, error_;
  PhaseTimes times_;
  std::thread thread_;  // last: started once the members it uses exist
};

}  // namespace canopy::mission
