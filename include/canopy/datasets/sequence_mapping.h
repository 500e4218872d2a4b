#pragma once
// Mapping a recorded sequence (canopy or TUM layout, frame_sequence.h): each frame is read and
// passes the mapping library's frame step (mapping/frame_mapping.h) in order. The same step
// maps in-memory frames, so a sequence written to files and read back builds the same map.

#include <functional>
#include <string>
#include <vector>

#include "canopy/datasets/frame_sequence.h"
#include "canopy/mapping/frame_mapping.h"

namespace canopy::datasets {

/// A sequence's mapping: one step per readable frame, and the frames skipped.
struct SequenceMapResult {
  std::vector<mapping::FrameMapStep> steps;
  std::vector<SkippedFrame> skipped;  ///< Skipped while opening and while reading.
  std::size_t mapped = 0;
  bool complete = true;               ///< False when `stop` ended it early.
};

/// Maps every frame of `frames` into the inserter's map; `on_frame` (may be null) is called
/// after each; `stop` (may be null) is polled before each and ends the run early when true. Throws InputError on a bad file (frame_sequence.h).
SequenceMapResult map_sequence(const FrameSequence& frames, perception::SemanticExtractor& extractor,
                               mapping::ScanInserter& inserter,
                               const std::function<void(const mapping::FrameMapStep&)>& on_frame = nullptr,
                               const std::function<bool()>& stop = nullptr);

}  // namespace canopy::datasets
