// The topics `canopy map --mcap` chooses from a recording's topic list (no file read): a table
// of lab conventions (canopy's own topics, RealSense, ZED, image_transport's raw and compressed
// pair, PNG colour beside compressed depth, a lone CameraInfo) against the expected choice, and
// the refusals: no candidate, several that nothing tells apart (naming them and the flag), a
// topic named that is absent or of another type, label images without a label topic.

#include "canopy/jobs/mcap_topics.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/ros2/messages.h"

namespace canopy::jobs {
namespace {

namespace msg = ros2::msg;

RecordingTopic image(const std::string& name, const std::string& encoding) {
  return {name, msg::Image::kTypeName, encoding};
}
RecordingTopic compressed(const std::string& name, const std::string& format) {
  return {name, msg::CompressedImage::kTypeName, format};
}
RecordingTopic info(const std::string& name) { return {name, msg::CameraInfo::kTypeName, ""}; }
RecordingTopic tf(const std::string& name) { return {name, msg::TFMessage::kTypeName, ""}; }

struct Case {
  const char* what;
  std::vector<RecordingTopic> topics;
  std::string depth, rgb, camera_info;  // expected
};

TEST(McapTopics, ChoosesEachConventionsTopics) {
  const std::vector<Case> cases = {
      {"canopy's own topics win over other candidates",
       {image("/canopy/wrist/depth", "32FC1"), image("/canopy/wrist/rgb", "rgb8"), image("/canopy/wrist/labels", "mono8"),
        image("/canopy/wrist/labels_color", "rgb8"), info("/canopy/wrist/camera_info"), image("/other/depth", "16UC1"),
        tf("/tf")},
       "/canopy/wrist/depth", "/canopy/wrist/rgb", "/canopy/wrist/camera_info"},
      {"RealSense: the aligned depth of two, the colour camera's info",
       {image("/camera/color/image_raw", "rgb8"), image("/camera/aligned_depth_to_color/image_raw", "16UC1"),
        image("/camera/depth/image_rect_raw", "16UC1"), info("/camera/color/camera_info"),
        info("/camera/depth/camera_info"), tf("/tf"), tf("/tf_static")},
       "/camera/aligned_depth_to_color/image_raw", "/camera/color/image_raw", "/camera/color/camera_info"},
      {"ZED: registered depth, bgra8 colour, the info beside the colour images",
       {image("/zed/zed_node/rgb/image_rect_color", "bgra8"), image("/zed/zed_node/depth/depth_registered", "32FC1"),
        image("/zed/zed_node/confidence/confidence_map", "32FC3"), info("/zed/zed_node/rgb/camera_info"),
        info("/zed/zed_node/depth/camera_info")},
       "/zed/zed_node/depth/depth_registered", "/zed/zed_node/rgb/image_rect_color", "/zed/zed_node/rgb/camera_info"},
      {"image_transport: the raw topic of a raw and /compressed pair; mono16 depth",
       {image("/cam/color/image_raw", "rgb8"), compressed("/cam/color/image_raw/compressed", "rgb8; png compressed bgr8"),
        image("/cam/depth/image_raw", "mono16"), info("/cam/color/camera_info")},
       "/cam/depth/image_raw", "/cam/color/image_raw", "/cam/color/camera_info"},
      {"PNG colour only compressed; compressed depth is no colour; the info beside the depth",
       {compressed("/camera/color/image_raw/compressed", "png"),
        compressed("/camera/depth/image_raw/compressedDepth", "16UC1; compressedDepth png"),
        image("/camera/depth/image_raw", "16UC1"), info("/camera/depth/camera_info")},
       "/camera/depth/image_raw", "/camera/color/image_raw/compressed", "/camera/depth/camera_info"},
      {"/color/ preferred among colour images; canopy's label colours are no colour camera; a lone info",
       {image("/robot/color/image", "rgb8"), image("/robot/ir/image", "rgb8"), image("/canopy/wrist/labels_color", "rgb8"),
        image("/robot/depth", "32FC1"), info("/calibration/intrinsics")},
       "/robot/depth", "/robot/color/image", "/calibration/intrinsics"},
      {"encodings canopy does not read are no candidates; unread topics (no encoding) neither",
       {image("/a/depth", "32FC1"), image("/a/disparity", "32FC3"), image("/a/empty", ""), image("/a/image", "rgb8"),
        image("/a/mono", "mono8"), info("/a/camera_info")},
       "/a/depth", "/a/image", "/a/camera_info"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    McapFrameOptions o;
    const std::vector<std::string> lines = choose_mcap_topics(c.topics, o);
    EXPECT_EQ(o.depth, c.depth);
    EXPECT_EQ(o.rgb, c.rgb);
    EXPECT_EQ(o.camera_info, c.camera_info);
    EXPECT_EQ(o.labels, "");
    EXPECT_EQ(lines, (std::vector<std::string>{"--depth " + c.depth + " (chosen from the recording)",
                                               "--rgb " + c.rgb + " (chosen from the recording)",
                                               "--camera-info " + c.camera_info + " (chosen from the recording)"}));
  }
}

TEST(McapTopics, NamedTopicsAreKeptAndOnlyTheRestChosen) {
  const std::vector<RecordingTopic> topics = {image("/camera/color/image_raw", "rgb8"),
                                              image("/camera/depth/image_rect_raw", "16UC1"),
                                              image("/camera/depth2/image_raw", "16UC1"),
                                              info("/camera/color/camera_info"),
                                              image("/canopy/wrist/labels", "mono8")};
  McapFrameOptions o;
  o.depth = "/camera/depth2/image_raw";  // names one of two ambiguous depth topics
  o.label_images = true;
  const std::vector<std::string> lines = choose_mcap_topics(topics, o);
  EXPECT_EQ(o.depth, "/camera/depth2/image_raw");
  EXPECT_EQ(o.labels, "/canopy/wrist/labels");
  EXPECT_EQ(lines, (std::vector<std::string>{"--rgb /camera/color/image_raw (chosen from the recording)",
                                             "--labels /canopy/wrist/labels (chosen from the recording)",
                                             "--camera-info /camera/color/camera_info (chosen from the recording)"}));
  McapFrameOptions named = o;
  EXPECT_TRUE(choose_mcap_topics(topics, named).empty()) << "every topic named: nothing chosen";
  EXPECT_FALSE(choice_needs_encodings(named));
  EXPECT_TRUE(choice_needs_encodings(McapFrameOptions{}));
  named.labels.clear();
  EXPECT_TRUE(choice_needs_encodings(named));  // a label topic to choose
  named.label_images = false;
  EXPECT_FALSE(choice_needs_encodings(named));  // labels not read
}

// The refusal's whole message (choose_mcap_topics adds no file name; McapFrames does).
std::string refusal(const std::vector<RecordingTopic>& topics, McapFrameOptions o) {
  try {
    choose_mcap_topics(topics, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(McapTopics, RefusesWhatIsMissingOrAmbiguous) {
  const RecordingTopic rgb = image("/camera/color/image_raw", "rgb8");
  const RecordingTopic depth = image("/camera/depth/image_raw", "16UC1");
  const RecordingTopic camera_info = info("/camera/color/camera_info");
  McapFrameOptions o;
  // Two depth topics, neither aligned nor registered: ambiguous, both named.
  EXPECT_EQ(refusal({rgb, depth, image("/camera/depth2/image_raw", "32FC1"), camera_info}, o),
            "several depth image (16UC1, mono16, 32FC1) topics (/camera/depth/image_raw, /camera/depth2/image_raw): "
            "name one with --depth");
  // Two aligned ones are as ambiguous.
  EXPECT_EQ(refusal({rgb, image("/a/aligned_depth", "16UC1"), image("/b/aligned_depth", "16UC1"), camera_info}, o),
            "several depth image (16UC1, mono16, 32FC1) topics (/a/aligned_depth, /b/aligned_depth): name one with --depth");
  // Two colour cameras, neither under /color/ or /rgb/.
  EXPECT_EQ(refusal({image("/left/image", "bgr8"), image("/right/image", "bgr8"), depth, camera_info}, o),
            "several colour image (rgb8, bgr8, rgba8, bgra8, PNG) topics (/left/image, /right/image): name one with --rgb");
  // No depth at all (a colour camera's recording).
  EXPECT_EQ(refusal({rgb, camera_info}, o),
            "no depth image (16UC1, mono16, 32FC1) topics (none): name one with --depth");
  // Two CameraInfo topics, neither beside the images.
  EXPECT_EQ(refusal({rgb, depth, info("/x/info"), info("/y/info")}, o),
            "several CameraInfo topics (/x/info, /y/info): name one with --camera-info");
  EXPECT_EQ(refusal({rgb, depth}, o), "no CameraInfo topics (none): name one with --camera-info");
  // A topic named that the recording lacks, or of another type.
  McapFrameOptions named;
  named.rgb = "/camera/infra1/image_rect_raw";
  EXPECT_EQ(refusal({rgb, depth, camera_info}, named),
            "--rgb /camera/infra1/image_rect_raw: no such topic (the recording has /camera/color/camera_info "
            "(sensor_msgs/msg/CameraInfo), /camera/color/image_raw (sensor_msgs/msg/Image), /camera/depth/image_raw "
            "(sensor_msgs/msg/Image))");
  named.rgb = "/camera/color/camera_info";
  EXPECT_EQ(refusal({rgb, depth, camera_info}, named),
            "--rgb /camera/color/camera_info: a topic of type sensor_msgs/msg/CameraInfo, not sensor_msgs/msg/Image, "
            "sensor_msgs/msg/CompressedImage");
  named.rgb.clear();
  named.camera_info = "/camera/color/image_raw";
  EXPECT_EQ(refusal({rgb, depth, camera_info}, named),
            "--camera-info /camera/color/image_raw: a topic of type sensor_msgs/msg/Image, not sensor_msgs/msg/CameraInfo");
  // Label images without canopy's label topic.
  McapFrameOptions labels;
  labels.label_images = true;
  EXPECT_EQ(refusal({rgb, depth, camera_info}, labels),
            "--seg truth reads label images: name their topic (mono8 class indices) with --labels");
}

}  // namespace
}  // namespace canopy::jobs
