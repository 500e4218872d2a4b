#include "canopy/datasets/sequence_mapping.h"

namespace canopy::datasets {

SequenceMapResult map_frames(std::size_t size, const std::function<bool(std::size_t, LabelledFrame*, std::string*)>& read,
                             const std::function<std::string(std::size_t)>& name, std::vector<SkippedFrame> skipped,
                             perception::SemanticExtractor& extractor, mapping::ScanInserter& inserter,
                             const std::function<void(const mapping::FrameMapStep&)>& on_frame,
                             const std::function<bool()>& stop) {
  SequenceMapResult result;
  result.skipped = std::move(skipped);
  for (std::size_t i = 0; i < size; ++i) {
    if (stop && stop()) {
      result.complete = false;
      break;
    }
    LabelledFrame frame;
    std::string why;
    mapping::FrameMapStep step;
    if (read(i, &frame, &why)) {
      step = mapping::map_frame(frame, extractor, inserter);
      ++result.mapped;
    } else {
      step.skip_reason = why;
      result.skipped.push_back({name(i), why});
    }
    step.name = name(i);
    if (on_frame) on_frame(step);
    result.steps.push_back(std::move(step));
  }
  return result;
}

SequenceMapResult map_sequence(const FrameSequence& frames, perception::SemanticExtractor& extractor,
                               mapping::ScanInserter& inserter, const std::function<void(const mapping::FrameMapStep&)>& on_frame,
                               const std::function<bool()>& stop) {
  return map_frames(
      frames.size(), [&](std::size_t i, LabelledFrame* f, std::string* why) { return frames.read(i, f, why); },
      [&](std::size_t i) { return frames.name(i); }, frames.skipped(), extractor, inserter, on_frame, stop);
}

}  // namespace canopy::datasets
