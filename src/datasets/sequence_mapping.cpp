#include "canopy/datasets/sequence_mapping.h"

namespace canopy::datasets {

SequenceMapResult map_sequence(const FrameSequence& frames, perception::SemanticExtractor& extractor,
                               mapping::ScanInserter& inserter, const std::function<void(const mapping::FrameMapStep&)>& on_frame,
                               const std::function<bool()>& stop) {
  SequenceMapResult result;
  result.skipped = frames.skipped();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (stop && stop()) {
      result.complete = false;
      break;
    }
    LabelledFrame frame;
    std::string why;
    mapping::FrameMapStep step;
    if (frames.read(i, &frame, &why)) {
      step = mapping::map_frame(frame, extractor, inserter);
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

}  // namespace canopy::datasets
