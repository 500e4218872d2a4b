#pragma once
// The frame step, the one way every caller (mission, ablation, `canopy map`, recorded
// sequences) turns a frame into map updates: label it with the extractor (colour
// segmentation, or the frame's label image with LabelSource::kTruth), add noise, unproject,
// insert.

#include <string>

#include "canopy/common/frame.h"
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

/// Labels and inserts one frame; the pixel labels it mapped (after noise) go to `mapped_labels`
/// when given (what a report thumbnails beside the true labels).
FrameMapStep map_frame(const LabelledFrame& frame, perception::SemanticExtractor& extractor, ScanInserter& inserter,
                       Image<std::uint8_t>* mapped_labels = nullptr);

}  // namespace canopy::mapping
