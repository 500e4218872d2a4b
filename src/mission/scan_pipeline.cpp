#include "scan_pipeline.h"

#include <utility>

#include "canopy/common/error.h"
#include "canopy/mission/mission.h"

namespace canopy::mission {

ScanPipeline::ScanPipeline(mapping::SemanticOcTree& map, mapping::ScanInserter& inserter, nbv::VoxelIndex& index,
                           evaluation::IncrementalEvaluator& evaluator, motion::CollisionEnvironment& environment,
                           records::MapReplay* replay)
    : map_(map), inserter_(inserter), index_(index), evaluator_(evaluator), environment_(environment), replay_(replay),
      thread_([this] { run(); }) {}

ScanPipeline::~ScanPipeline() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void ScanPipeline::start(perception::LabelledCloud cloud, bool metrics) {
  CANOPY_CHECK(!busy_, "the last scan is not settled");
  {
    std::lock_guard<std::mutex> lock(mutex_);
    cloud_ = std::move(cloud);
    metrics_ = metrics;
    insert_error_ = index_error_ = error_ = nullptr;
    times_ = PhaseTimes{};
    stage_ = Stage::kQueued;
  }
  changed_.notify_all();
  busy_ = unfollowed_ = true;
}

void ScanPipeline::run() {
  for (;;) {
    bool metrics = false;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return quit_ || stage_ == Stage::kQueued; });
      if (stage_ != Stage::kQueued) return;  // quit, nothing queued
      metrics = metrics_;
    }
    // The caller touches none of these until kInserted (the map, the inserter), kIndexed (the
    // index) or kDone. Each step runs unless one before it failed, then says how far it got.
    PhaseTimes t;
    std::exception_ptr error;
    // A step without a phase does nothing.
    auto step = [&](const char* phase, Stage reached, std::exception_ptr* outcome, const auto& work) {
      if (!error) {
        try {
          if (phase) {
            ScopedPhase phase_time(t, phase);
            work();
          }
        } catch (...) {
          error = std::current_exception();
        }
      }
      {
        std::lock_guard<std::mutex> lock(mutex_);
        *outcome = error;
        stage_ = reached;
        if (reached == Stage::kDone) times_ = t;
      }
      changed_.notify_all();
    };
    const std::uint64_t revision = map_.revision();
    step(to_string(WallPhase::kMapping), Stage::kInserted, &insert_error_, [&] { inserter_.insert(cloud_); });
    step(to_string(WallPhase::kMapping), Stage::kIndexed, &index_error_,
         [&] { index_.apply_updates(map_, revision, inserter_.last_updates()); });
    // No metrics and no replay: nothing to do.
    step(metrics ? to_string(WallPhase::kEvaluation) : replay_ ? to_string(WallPhase::kMapping) : nullptr, Stage::kDone, &error_, [&] {
      if (metrics) evaluator_.update(map_, inserter_.last_updates());
      if (replay_) replay_->record_scan(map_, inserter_.last_updates(), &inserter_.last_occupancy());
      if (replay_ && metrics) replay_->record_fruits(evaluator_.metrics());
    });
  }
}

void ScanPipeline::follow() {
  if (!unfollowed_) return;
  unfollowed_ = false;
  std::exception_ptr error;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return stage_ == Stage::kInserted || stage_ == Stage::kIndexed || stage_ == Stage::kDone; });
    error = insert_error_;
  }
  if (error) std::rethrow_exception(error);
  environment_.follow_scan(map_, inserter_.last_updates(), inserter_.last_occupancy());
}

void ScanPipeline::follow_index() {
  if (!busy_) return;
  follow();  // rethrows an error of the insertion
  std::exception_ptr error;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return stage_ == Stage::kIndexed || stage_ == Stage::kDone; });
    error = index_error_;
  }
  if (error) std::rethrow_exception(error);
}

PhaseTimes ScanPipeline::settle() {
  if (!busy_) return {};
  follow();  // rethrows an error of the insertion
  std::exception_ptr error;
  PhaseTimes t;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return stage_ == Stage::kDone; });
    stage_ = Stage::kIdle;
    error = error_;
    t = times_;
  }
  busy_ = false;
  if (error) std::rethrow_exception(error);
  return t;
}

}  // namespace canopy::mission
