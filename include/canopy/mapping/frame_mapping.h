#pragma once
// Mapping a recorded sequence (canopy or TUM layout, common/frame_sequence.h): each frame is
// read, labelled by the extractor (colour segmentation, or the frame's label image with
// LabelSource::kTruth) and inserted, in order. The same path maps in-memory frames, so a
// sequence written to files and read back builds the same map.

#include <functional>
#include <string>
#include <vector>

#include "canopy/common/frame_sequence.h"
#include "canopy/mapping/scan_inserter.h"
#include "canopy/perception/semantic_extractor.h"

namespace canopy::mapping {

/// What happened to one frame.
struct FrameMapStep {
  std::string name;
  bool mapped = false;
  std::string skip_reason;          ///< Why not, when !mapped.
  perception::ExtractStats extract;
  InsertStats insert;
};

/// A sequence's mapping: one step per readable frame, and the frames skipped.
struct SequenceMapResult {
  std::vector<FrameMapStep> steps;
  std::vector<SkippedFrame> skipped;  ///< Skipped while opening and while reading.
  std::size_t mapped = 0;
};

/// Labels and inserts one frame.
FrameMapStep map_frame(const LabelledFrame& frame, perception::SemanticExtractor& extractor, ScanInserter& inserter);

/// Maps every frame of `frames` into the inserter's map; `on_frame` (may be null) is called
/// after each. Throws InputError on a bad file (frame_sequence.h).
SequenceMapResult map_sequence(const FrameSequence& frames, perception::SemanticExtractor& extractor,
                               ScanInserter& inserter,
                               const std::function<void(const FrameMapStep&)>& on_frame = nullptr);

}  // namespace canopy::mapping
