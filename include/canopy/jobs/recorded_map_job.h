#pragma once
// Job: map a recorded sequence into a run folder. What `canopy map --frames` does with a frame
// folder (canopy or TUM layout) and Python's `python3 -m canopy map-bag` with a ROS bag: each
// frame passes the frame step (mapping/frame_mapping.h) in order, and the folder gets map.csm,
// map.ply, map.bt, frames.json (per frame: its insertion figures or why it was skipped),
// run.yaml (the source, as the caller describes it) and settings.yaml. No ground truth, so
// no coverage.

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "canopy/common/classes.h"
#include "canopy/common/frame.h"
#include "canopy/datasets/frame_sequence.h"
#include "canopy/mapping/frame_mapping.h"
#include "canopy/settings/settings.h"

namespace canopy::jobs {

/// A recorded sequence, read one frame at a time.
struct RecordedSequence {
  std::string source;                                   ///< What it is, in messages (a folder, a bag).
  SemanticClasses classes;                              ///< The classes of its labels (and of the map).
  std::size_t size = 0;                                 ///< Frames to read.
  std::function<std::string(std::size_t)> name;         ///< Frame i's name.
  /// Reads frame i; false with `why` when it cannot be mapped (it is skipped and counted).
  std::function<bool(std::size_t, LabelledFrame*, std::string*)> read;
  std::vector<datasets::SkippedFrame> skipped;          ///< Dropped before reading (no partner, no pose).
  std::vector<std::string> notes;                       ///< What the reader changed or assumed.
  YAML::Node run;  ///< run.yaml: the command and the source's options (map_recorded adds p_gt when absent).
};

/// What map_recorded needs besides the sequence.
struct RecordedMapParams {
  settings::Settings settings;                           ///< Mapping section used; saved as settings.yaml.
  std::string out;                                      ///< Output folder.
  std::string out_option = "--out";                     ///< Its name in messages.
  std::function<void(const mapping::FrameMapStep&)> on_frame;  ///< After each frame (may be null).
  std::function<bool()> stop_requested;                 ///< Polled before each frame (may be null).
};

/// What it did.
struct RecordedMapResult {
  std::size_t mapped = 0, skipped = 0, occupied_voxels = 0;
  bool complete = true;
};

/// A frame folder (canopy's or TUM RGB-D, datasets::FrameSequence) as a sequence to map, with
/// run.yaml's description of it: the command, the folder, its layout, where labels come from,
/// the classes and the pairing tolerance. `frames` must outlive the sequence.
RecordedSequence frames_sequence(const datasets::FrameSequence& frames, const datasets::FrameReaderOptions& reader);

/// Maps the sequence and publishes the folder. Throws InputError when no frame could be
/// mapped, Interrupted when stopped (before the first frame: nothing written; after it: the
/// frames so far are published, frames.json "complete": false).
RecordedMapResult map_recorded(const RecordedSequence& frames, const RecordedMapParams& params);

}  // namespace canopy::jobs
