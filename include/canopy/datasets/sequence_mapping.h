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

/// Maps `size` frames, each read by `read(i, &frame, &why)` (false: skipped with `why`) and
/// named by `name(i)`, into the inserter's map; `skipped` holds the frames dropped before
/// reading. `on_frame` and `stop` as in map_sequence. Any source of frames (a folder, a bag).
SequenceMapResult map_frames(std::size_t size, const std::function<bool(std::size_t, LabelledFrame*, std::string*)>& read,
                             const std::function<std::string(std::size_t)>& name, std::vector<SkippedFrame> skipped,
                             perception::SemanticExtractor& extractor, mapping::ScanInserter& inserter,
                             const std::function<void(const mapping::FrameMapStep&)>& on_frame = nullptr,
                             const std::function<bool()>& stop = nullptr);

/// Maps every frame of `frames` into the inserter's map; `on_frame` (may be null) is called
/// after each; `stop` (may be null) is polled before each and ends the run early when true. Throws InputError on a bad file (frame_sequence.h).
SequenceMapResult map_sequence(const FrameSequence& frames, perception::SemanticExtractor& extractor,
                               mapping::ScanInserter& inserter,
                               const std::function<void(const mapping::FrameMapStep&)>& on_frame = nullptr,
                               const std::function<bool()>& stop = nullptr);

}  // namespace canopy::datasets
