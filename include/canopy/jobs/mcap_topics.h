#pragma once
// Which topics of a ROS 2 recording `canopy map --mcap` reads when the options leave them open
// (McapFrameOptions: --depth, --rgb, --labels, --camera-info): canopy's own topics when the
// recording has them; else the one image topic whose first image has a depth (or colour)
// encoding, the one named as aligned / registered (or /color/, /rgb/) among several, the raw
// topic of image_transport's NAME and NAME/compressed; the CameraInfo beside the colour (or
// depth) images, else the only one. No candidate, or several that nothing tells apart, is
// refused: InputError naming the candidates and the flag that names one. The camera's poses
// are no choice: they are /tf and /tf_static, and McapFrames takes --world-frame from their tree.
//
//   std::vector<RecordingTopic> topics = {{"/camera/color/image_raw", "sensor_msgs/msg/Image", "rgb8"}, ...};
//   McapFrameOptions o;  // every topic left open
//   for (const std::string& line : choose_mcap_topics(topics, o)) std::puts(line.c_str());

#include <string>
#include <vector>

#include "canopy/jobs/mcap_frames.h"

namespace canopy::jobs {

/// A topic of a recording as the choice sees it.
struct RecordingTopic {
  std::string name;
  std::string type;      ///< Its message type ("sensor_msgs/msg/Image").
  std::string encoding;  ///< Its first image's encoding (Image) or format (CompressedImage); "": not read.
};

/// The depth encodings canopy reads: 16UC1 and mono16 (mm), 32FC1 (m).
bool is_depth_encoding(const std::string& encoding);
/// The colour encodings canopy reads from an Image: rgb8, bgr8, rgba8, bgra8.
bool is_colour_encoding(const std::string& encoding);
/// The class-label encodings canopy reads: mono8, 8UC1.
bool is_label_encoding(const std::string& encoding);
/// A CompressedImage format that is PNG ("png", "rgb8; png compressed bgr8", ...).
bool is_png(const std::string& format);

/// True when choose_mcap_topics reads the image topics' encodings for `o` (a depth, colour or
/// label topic to choose); else RecordingTopic::encoding may be left "".
bool choice_needs_encodings(const McapFrameOptions& o);

/// Fills in what `o` leaves open of depth, rgb, labels (with label_images) and camera_info from
/// `topics` (in the recording's order; a name listed twice counts once, as first listed) and
/// checks every topic named against its type. Returns one line per choice made ("--depth NAME
/// (chosen from the recording)"). InputError without the file's name (the caller adds it) when a
/// choice has no candidate or several, or a topic named is absent or of another type.
std::vector<std::string> choose_mcap_topics(const std::vector<RecordingTopic>& topics, McapFrameOptions& o);

}  // namespace canopy::jobs
