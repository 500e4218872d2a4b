#include "canopy/mapping/frame_mapping.h"

namespace canopy::mapping {

FrameMapStep map_frame(const LabelledFrame& frame, perception::SemanticExtractor& extractor, ScanInserter& inserter,
                       Image<std::uint8_t>* mapped_labels) {
  FrameMapStep step;
  const perception::LabelledCloud cloud = extractor.extract(frame, mapped_labels);
  step.extract = cloud.stats;
  step.insert = inserter.insert(cloud);
  step.mapped = true;
  return step;
}

}  // namespace canopy::mapping
