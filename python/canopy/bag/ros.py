"""What the bag modules share: the error type, the topics and frames canopy writes, the ROS 1
libraries (imported on first use) and ROS time in nanoseconds. Imports none of its siblings."""

import sys
import types

# Topics and frames canopy writes (and map-bag reads by default).
TOPICS = {
    "rgb": "/canopy/wrist/rgb",
    "depth": "/canopy/wrist/depth",
    "labels": "/canopy/wrist/labels",
    "labels_color": "/canopy/wrist/labels_color",
    "camera_info": "/canopy/wrist/camera_info",
    "map": "/canopy/map",
    "views": "/canopy/views",
    "view_record": "/canopy/view_record",
    "fruits": "/canopy/fruits",
}
WORLD_FRAME = "world"
# A bag canopy wrote carries one message on this topic (std_msgs/String, "written by canopy ...")
# whose connection header holds WRITER_FIELD. Only a bag written with rosbag's Python API by
# canopy has that field: a recording of a canopy bag played back (rosbag record) carries the
# topic but not the field, so canopy never takes it for its own.
WRITER_TOPIC = "/canopy/written_by"
WRITER_FIELD = "canopy_writer"
# The classes of label images when none are given (canopy's default classes, SemanticClasses).
DEFAULT_CLASSES = ("background", "leaf", "fruit")
# Largest difference between a depth image's stamp and its RGB, label and camera_info partners,
# and how far before the first or after the last sample of a transform it is still taken [s].
DEFAULT_MAX_DT = 0.02

IMAGE = "sensor_msgs/Image"
COMPRESSED = "sensor_msgs/CompressedImage"
CAMERA_INFO = "sensor_msgs/CameraInfo"
TF_MESSAGE = "tf2_msgs/TFMessage"


class BagError(ValueError):
    """A bag that cannot be read or written as asked (the message names the topic, frame,
    transform or file)."""


def ros():
    """Debian's ROS 1 Python packages, imported on first use."""
    try:
        import genpy
        import rosbag
        from geometry_msgs import msg as geometry_msgs
        from sensor_msgs import msg as sensor_msgs
        from std_msgs import msg as std_msgs
        from tf2_msgs import msg as tf2_msgs
        from visualization_msgs import msg as visualization_msgs
    except ImportError as e:
        raise ImportError(
            f"canopy's ROS bags need Debian's python3-rosbag, python3-sensor-msgs, python3-geometry-msgs, "
            f"python3-tf2-msgs and python3-visualization-msgs (tools/deps.sh) in this interpreter "
            f"({sys.executable}; the system one is /usr/bin/python3): {e}") from None
    return types.SimpleNamespace(genpy=genpy, rosbag=rosbag, geometry=geometry_msgs, sensor=sensor_msgs,
                                 std=std_msgs, tf2=tf2_msgs, viz=visualization_msgs)


def ns_of(stamp):
    """A ROS time (genpy.Time) in integer nanoseconds."""
    return int(stamp.secs) * 1_000_000_000 + int(stamp.nsecs)


def seconds(ns):
    """Nanoseconds as text for messages."""
    return f"{ns / 1e9:.9f} s"


def short(text, limit=160):
    """One line of at most `limit` characters (values from a bag can be anything)."""
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[:limit - 3] + "..."
