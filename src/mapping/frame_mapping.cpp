#include "canopy/mapping/frame_mapping.h"

namespace canopy::mapping {

FrameMapStep map_frame(const LabelledFrame& frame, perception::SemanticExtractor& extractor, ScanInserter& inserter) {
  FrameMapStep step;
  const perception::LabelledCloud cloud = extractor.extract(frame);
  step.extract = cloud.stats;
  step.insert = inserter.insert(cloud);
  step.mapped = true;
  return step;
}

SequenceMapResult map_sequence(const FrameSequence& frames, perception::SemanticExtractor& extractor,
                               ScanInserter& inserter, const std::function<void(const FrameMapStep&)>& on_frame) {
  SequenceMapResult result;
  result.skipped = frames.skipped();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    LabelledFrame frame;
    std::string why;
    FrameMapStep step;
    if (frames.read(i, &frame, &why)) {
      step = map_frame(frame, extractor, inserter);
      ++result.mapped;
    } else {
      step.skip_reason = why;
      result.skipped.push_back({frames.name(i), why});
    }
    step.name = frames.name(i);
    if (on_frame) on_frame(step);
    result.steps.push_back(std::move(step));
  }
  return result;
}

}  // namespace canopy::mapping
