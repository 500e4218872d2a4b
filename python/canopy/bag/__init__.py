"""ROS 1 bags in and out (docs/real_robot.md#ros-bags).

- read_bag(path, rgb=, depth=, camera_info=, labels=, frame=, world_frame=): a lab's recording
  as canopy.Frame objects (RGB, depth, intrinsics, the camera's pose from /tf and /tf_static),
  which Map.insert, canopy.map_frames and the planners take; all of them in memory.
- BagReader(path, ...): the same, streamed: len(), skipped, notes, and frames(), a generator
  decoding one frame at a time.
- map_bag(path, out, settings): a recording mapped into the run folder `canopy map --frames`
  writes, streamed (memory does not grow with the recording's length).
- record_bag(world, path, ...): runs the mission (canopy.run_mission) and writes it as a bag
  while it runs: wrist RGB, depth, labels and camera_info, /tf of the base, the arm's links and
  the camera over simulated time, the map at each view (PointCloud2 in class colours), the
  views (MarkerArray frustums by phase, in the report's phase colours), each view's record
  (std_msgs/String JSON of the views' schema: the names of views.csv and the report) and the
  true fruits (MarkerArray boxes).
- export_bag(run_dir, path): the bag of a finished `canopy mission` run folder, by replaying
  the run from its own records (settings.yaml, the world's resolved spec and the seed in
  summary.json); refused unless the replay's views.csv equals the run's byte for byte.
- is_canopy_bag(path): whether canopy wrote the bag at path (only such a bag is replaced).

The bags are ROS 1 bags (format 2.0) written and read with Debian's python3-rosbag; no ROS
installation or roscore is needed. Bad input raises BagError (a ValueError) naming the topic,
frame, transform or file; `python3 -m canopy map-bag / export-bag` print it as one line, exit
code 2.

Modules: ros (the error, topics and the ROS libraries), poses (transforms and the /tf tree),
read and write; none imports this package's __init__.
"""

from .read import BagReader, map_bag, read_bag  # noqa: F401
from .ros import (DEFAULT_CLASSES, DEFAULT_MAX_DT, TOPICS, WORLD_FRAME, WRITER_TOPIC, BagError)  # noqa: F401
from .write import (FRUSTUM_DEPTH_M, PHASE_COLORS, VIEW_RECORD_FIELDS, export_bag, is_canopy_bag,  # noqa: F401
                    record_bag, view_record_json)
