"""ROS 1 bags in and out (docs/real_robot.md#ros-bags).

- read_bag(path, rgb=, depth=, camera_info=, labels=, frame=, world_frame=): a lab's recording
  as canopy.Frame objects (RGB, depth, intrinsics, the camera's pose from /tf and /tf_static),
  which Map.insert, canopy.map_frames and the planners take.
- record_bag(world, path, ...): runs the mission (canopy.run_mission) and writes it as a bag
  while it runs: wrist RGB, depth, labels and camera_info, /tf of the base, the arm's links and
  the camera over simulated time, the map at each view (PointCloud2 in class colours), the
  views (MarkerArray frustums by phase) and the true fruits (MarkerArray boxes).
- export_bag(run_dir, path): the bag of a finished `canopy mission` run folder, by replaying
  the run from its own records (settings.yaml, the world's resolved spec and the seed in
  summary.json); refused unless the replay's views.csv equals the run's byte for byte.

The bags are ROS 1 bags (format 2.0) written and read with Debian's python3-rosbag; no ROS
installation or roscore is needed. Bad input raises BagError (a ValueError) naming the topic,
frame or transform; `python3 -m canopy map-bag / export-bag` print it as one line, exit code 2.
"""

import bisect
import io
import math
import os
import sys
import types

import numpy as np

from . import _canopy

# Topics and frames canopy writes (and map-bag reads by default).
TOPICS = {
    "rgb": "/canopy/wrist/rgb",
    "depth": "/canopy/wrist/depth",
    "labels": "/canopy/wrist/labels",
    "labels_color": "/canopy/wrist/labels_color",
    "camera_info": "/canopy/wrist/camera_info",
    "map": "/canopy/map",
    "views": "/canopy/views",
    "fruits": "/canopy/fruits",
}
WORLD_FRAME = "world"
# The classes of label images when none are given (canopy's default classes, SemanticClasses).
DEFAULT_CLASSES = ("background", "leaf", "fruit")
# Largest difference between a depth image's stamp and its RGB, label and camera_info partners,
# and how far before the first or after the last sample of a transform it is still taken [s].
DEFAULT_MAX_DT = 0.02
# Colours of the view frustums by phase (RGBA).
PHASE_COLORS = {
    "initial": (0.2, 0.5, 1.0, 1.0),
    "nbv": (1.0, 0.55, 0.0, 1.0),
    "predefined": (0.6, 0.6, 0.6, 1.0),
}
FRUSTUM_DEPTH_M = 0.1

IMAGE = "sensor_msgs/Image"
COMPRESSED = "sensor_msgs/CompressedImage"
CAMERA_INFO = "sensor_msgs/CameraInfo"
TF_MESSAGE = "tf2_msgs/TFMessage"


class BagError(ValueError):
    """A bag that cannot be read as asked (the message names the topic, frame or transform)."""


def _ros():
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


# --- poses ------------------------------------------------------------------------------------

def _quat_from_matrix(R):
    """Unit quaternion (x, y, z, w) of a rotation matrix (Shepperd's method)."""
    t = R[0, 0] + R[1, 1] + R[2, 2]
    if t > 0.0:
        s = math.sqrt(t + 1.0) * 2.0
        w, x, y, z = 0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s
    elif R[0, 0] > R[1, 1] and R[0, 0] > R[2, 2]:
        s = math.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2]) * 2.0
        w, x, y, z = (R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s
    elif R[1, 1] > R[2, 2]:
        s = math.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2]) * 2.0
        w, x, y, z = (R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s, (R[1, 2] + R[2, 1]) / s
    else:
        s = math.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1]) * 2.0
        w, x, y, z = (R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, 0.25 * s
    q = np.array([x, y, z, w])
    return q / np.linalg.norm(q)


def _matrix(t, q):
    """4x4 transform from a translation and a unit quaternion (x, y, z, w)."""
    x, y, z, w = q
    T = np.eye(4)
    T[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    T[:3, 3] = t
    return T


def _inverse(T):
    out = np.eye(4)
    out[:3, :3] = T[:3, :3].T
    out[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return out


def _slerp(q0, q1, s):
    d = float(np.dot(q0, q1))
    if d < 0.0:
        q1, d = -q1, -d
    if d > 0.9995:
        q = q0 + s * (q1 - q0)
    else:
        a = math.acos(d)
        q = (math.sin((1 - s) * a) * q0 + math.sin(s * a) * q1) / math.sin(a)
    return q / np.linalg.norm(q)


def _ns(stamp):
    """A ROS time (genpy.Time) in integer nanoseconds."""
    return int(stamp.secs) * 1_000_000_000 + int(stamp.nsecs)


def _seconds(ns):
    return f"{ns / 1e9:.9f} s"


# --- reading ----------------------------------------------------------------------------------

class _Transforms:
    """The bag's /tf and /tf_static: one parent per frame, time-stamped samples of the dynamic
    edges (sorted by stamp; at equal stamps the later message wins)."""

    def __init__(self, max_dt_ns):
        self.parent = {}       # child -> parent
        self.static = {}       # child -> 4x4
        self.samples = {}      # child -> ([stamps], [(t, q)])
        self.topic_of = {}     # child -> the topic that first gave it
        self.max_dt_ns = max_dt_ns

    def add(self, tfm, topic, is_static):
        child, parent = tfm.child_frame_id.lstrip("/"), tfm.header.frame_id.lstrip("/")
        if not child or not parent:
            raise BagError(f"{topic}: a transform with an empty frame name ('{parent}' -> '{child}')")
        known = self.parent.get(child)
        if known is not None and known != parent:
            raise BagError(f"{topic}: frame '{child}' has two parents, '{known}' and '{parent}' (a tf tree has one)")
        self.parent[child] = parent
        self.topic_of.setdefault(child, topic)
        r, p = tfm.transform.rotation, tfm.transform.translation
        q = np.array([r.x, r.y, r.z, r.w], dtype=float)
        n = float(np.linalg.norm(q))
        if not (abs(n - 1.0) < 1e-3) or not np.all(np.isfinite([p.x, p.y, p.z])):
            raise BagError(f"{topic}: transform '{parent}' -> '{child}' at {_seconds(_ns(tfm.header.stamp))} is not a "
                           f"rigid transform (quaternion norm {n:.6g}, translation {p.x}, {p.y}, {p.z})")
        t = np.array([p.x, p.y, p.z], dtype=float)
        q = q / n
        if is_static:
            if child in self.samples:
                raise BagError(f"{topic}: frame '{child}' is both in /tf and /tf_static")
            self.static[child] = _matrix(t, q)
            return
        if child in self.static:
            raise BagError(f"{topic}: frame '{child}' is both in /tf and /tf_static")
        stamps, values = self.samples.setdefault(child, ([], []))
        ns = _ns(tfm.header.stamp)
        i = bisect.bisect_right(stamps, ns)
        if i > 0 and stamps[i - 1] == ns:
            values[i - 1] = (t, q)
        else:
            stamps.insert(i, ns)
            values.insert(i, (t, q))

    def frames(self):
        return sorted(set(self.parent) | set(self.parent.values()))

    def chain(self, frame):
        """The frames from `frame` up to its root."""
        out = [frame]
        while out[-1] in self.parent:
            out.append(self.parent[out[-1]])
            if len(out) > 10000:
                raise BagError(f"/tf: the frames above '{frame}' form a cycle")
        return out

    def check_path(self, source, target):
        """BagError unless a transform from `source` to `target` exists in the tree."""
        known = set(self.frames())
        for name, what in ((source, "frame"), (target, "world_frame")):
            if name not in known:
                listed = ", ".join(self.frames()) or "none"
                raise BagError(f"{what} '{name}' is not in the bag's /tf or /tf_static (its frames: {listed})")
        a, b = self.chain(source), self.chain(target)
        if a[-1] != b[-1]:
            raise BagError(f"no transform from '{target}' to '{source}' in /tf and /tf_static: they are in separate "
                           f"trees (roots '{b[-1]}' and '{a[-1]}'); a transform between the trees is missing")

    def _edge(self, child, ns):
        """T_parent_child at time ns, or a string saying why there is none."""
        if child in self.static:
            return self.static[child]
        stamps, values = self.samples[child]
        i = bisect.bisect_left(stamps, ns)
        if i < len(stamps) and stamps[i] == ns:
            return _matrix(*values[i])
        edge = f"'{self.parent[child]}' -> '{child}'"
        if i == 0 or i == len(stamps):
            j = 0 if i == 0 else len(stamps) - 1
            if abs(stamps[j] - ns) <= self.max_dt_ns:
                return _matrix(*values[j])
            side = "before the first" if i == 0 else "after the last"
            return f"no /tf {edge} at {_seconds(ns)} ({side} sample, {_seconds(stamps[j])}, by more than max_dt)"
        (t0, q0), (t1, q1) = values[i - 1], values[i]
        s = (ns - stamps[i - 1]) / (stamps[i] - stamps[i - 1])
        return _matrix(t0 + s * (t1 - t0), _slerp(q0, q1, s))

    def lookup(self, target, source, ns):
        """T_target_source at time ns (interpolated), or a string saying why there is none."""
        a, b = self.chain(source), self.chain(target)
        common = next(f for f in a if f in set(b))

        def up(chain):
            T = np.eye(4)
            for child in chain[:chain.index(common)]:
                E = self._edge(child, ns)
                if isinstance(E, str):
                    return E
                T = E @ T
            return T

        T_common_source, T_common_target = up(a), up(b)
        for T in (T_common_source, T_common_target):
            if isinstance(T, str):
                return T
        return _inverse(T_common_target) @ T_common_source


def _open(path):
    ros = _ros()
    if not os.path.isfile(path):
        raise BagError(f"{path}: no such file")
    try:
        return ros.rosbag.Bag(path, "r")
    except Exception as e:  # rosbag raises its own exceptions and ValueError for what is no bag
        raise BagError(f"{path}: not a readable ROS 1 bag ({type(e).__name__}: {e})") from None


def _check_topic(topics, path, topic, role, types_ok):
    if topic not in topics:
        listed = ", ".join(sorted(topics)) or "none"
        raise BagError(f"{path}: topic {topic} ({role}) is not in the bag (its topics: {listed})")
    kind = topics[topic].msg_type
    if kind not in types_ok:
        raise BagError(f"{path}: topic {topic} ({role}) is {kind}, not {' or '.join(types_ok)}")


def _pixels(msg, topic, dtype, channels):
    """A sensor_msgs/Image's pixels as an (H, W[, C]) array of `dtype` (row padding and byte order
    handled)."""
    item = np.dtype(dtype).newbyteorder(">" if msg.is_bigendian else "<")
    row = msg.width * channels * item.itemsize
    if msg.step < row or len(msg.data) < msg.step * msg.height:
        raise BagError(f"{topic}: image data of {len(msg.data)} bytes with step {msg.step} does not hold "
                       f"{msg.height} rows of {msg.width} x {channels} {np.dtype(dtype).name}")
    raw = np.frombuffer(msg.data, dtype=np.uint8, count=msg.step * msg.height).reshape(msg.height, msg.step)
    a = np.ascontiguousarray(raw[:, :row]).view(item).astype(dtype)
    return a.reshape(msg.height, msg.width, channels) if channels > 1 else a.reshape(msg.height, msg.width)


def _decode_compressed(msg, topic):
    try:
        from PIL import Image as PILImage
    except ImportError:
        raise ImportError("compressed images need Debian's python3-pil (tools/deps.sh)") from None
    data = bytes(msg.data)
    if "compresseddepth" in msg.format.lower().replace(" ", ""):
        data = data[12:]  # compressed_depth_image_transport's header: format and two quantisation floats
    try:
        return PILImage.open(io.BytesIO(data)), bytes(msg.data)[:12]
    except Exception as e:
        raise BagError(f"{topic}: a CompressedImage ({msg.format}) that cannot be decoded: {e}") from None


DEPTH_ENCODINGS = "16UC1 or mono16 (millimetres), 32FC1 (metres)"
RGB_ENCODINGS = "rgb8, bgr8, rgba8, bgra8 or a jpeg / png CompressedImage"
LABEL_ENCODINGS = "mono8 or 8UC1 (class indices), rgb8 or bgr8 (class colours)"


def _depth(msg, topic):
    """The depth image and its unit: (uint16 array, 0.001) for millimetres (as canopy.Frame and
    the frame folders' 16-bit PNGs scale them), or (float32 metres, None); 0 = invalid."""
    if hasattr(msg, "encoding"):
        enc = msg.encoding
        if enc in ("16UC1", "mono16"):
            return _pixels(msg, topic, np.uint16, 1), 0.001
        elif enc == "32FC1":
            d = _pixels(msg, topic, np.float32, 1)
        else:
            raise BagError(f"{topic}: depth encoding '{enc}' is not supported ({DEPTH_ENCODINGS})")
    else:
        fmt = msg.format.replace(" ", "")
        if "compresseddepth" not in fmt.lower():
            raise BagError(f"{topic}: CompressedImage format '{msg.format}' is not compressedDepth ({DEPTH_ENCODINGS})")
        image, header = _decode_compressed(msg, topic)
        raw = np.asarray(image)
        if fmt.startswith("16UC1"):
            return raw.astype(np.uint16), 0.001
        elif fmt.startswith("32FC1"):  # inverse depth, quantised: z = a / (v - b)
            a, b = np.frombuffer(header[4:12], dtype="<f4")
            v = raw.astype(np.float32)
            with np.errstate(divide="ignore", invalid="ignore"):
                d = np.where(v > 0, a / (v - b), 0).astype(np.float32)
        else:
            raise BagError(f"{topic}: compressedDepth format '{msg.format}' is not supported ({DEPTH_ENCODINGS})")
    return np.where(np.isfinite(d) & (d > 0), d, 0).astype(np.float32), None


def _rgb(msg, topic):
    if hasattr(msg, "encoding"):
        enc = msg.encoding
        if enc in ("rgb8", "bgr8"):
            a = _pixels(msg, topic, np.uint8, 3)
        elif enc in ("rgba8", "bgra8"):
            a = _pixels(msg, topic, np.uint8, 4)[:, :, :3]
        else:
            raise BagError(f"{topic}: colour encoding '{enc}' is not supported ({RGB_ENCODINGS})")
        return np.ascontiguousarray(a[:, :, ::-1] if enc.startswith("bgr") else a)
    image, _ = _decode_compressed(msg, topic)
    return np.asarray(image.convert("RGB"), dtype=np.uint8)


def _labels(msg, topic, colors):
    if hasattr(msg, "encoding") and msg.encoding in ("mono8", "8UC1"):
        ids = _pixels(msg, topic, np.uint8, 1)
    elif hasattr(msg, "encoding") and msg.encoding in ("rgb8", "bgr8"):
        rgb = _pixels(msg, topic, np.uint8, 3)
        if msg.encoding == "bgr8":
            rgb = rgb[:, :, ::-1]
        code = (rgb[..., 0].astype(np.int64) << 16) | (rgb[..., 1].astype(np.int64) << 8) | rgb[..., 2]
        table = {int(c[0]) << 16 | int(c[1]) << 8 | int(c[2]): i for i, c in enumerate(colors)}
        ids = np.full(code.shape, 255, dtype=np.uint8)
        for value, i in table.items():
            ids[code == value] = i
        bad = np.argwhere(ids == 255)
        if len(bad):
            r, c = bad[0]
            raise BagError(f"{topic}: pixel ({c}, {r}) has colour {tuple(int(v) for v in rgb[r, c])}, which is no "
                           f"class's colour")
        return ids
    else:
        enc = getattr(msg, "encoding", getattr(msg, "format", "?"))
        raise BagError(f"{topic}: label encoding '{enc}' is not supported ({LABEL_ENCODINGS})")
    if ids.size and int(ids.max()) >= len(colors):
        r, c = np.argwhere(ids >= len(colors))[0]
        raise BagError(f"{topic}: pixel ({c}, {r}) has class {int(ids[r, c])}, but there are {len(colors)} classes")
    return ids


def _intrinsics(msg, topic, min_range, max_range):
    """canopy.Intrinsics of a CameraInfo. ROS puts pixel centres at integer coordinates, canopy
    at +0.5: cx and cy move by half a pixel."""
    K = list(msg.K)
    if len(K) != 9 or K[0] <= 0 or K[4] <= 0:
        raise BagError(f"{topic}: camera_info K = {K} has no focal lengths")
    try:
        return _canopy.Intrinsics(int(msg.width), int(msg.height), float(K[0]), float(K[4]), float(K[2]) + 0.5,
                                  float(K[5]) + 0.5, min_range, max_range)
    except ValueError as e:
        raise BagError(f"{topic}: {e}") from None


def _nearest(stamps, ns):
    """Index of the stamp nearest ns (-1 when there is none)."""
    if not stamps:
        return -1
    i = bisect.bisect_left(stamps, ns)
    best = [j for j in (i - 1, i) if 0 <= j < len(stamps)]
    return min(best, key=lambda j: abs(stamps[j] - ns))


def read_bag(path, rgb=TOPICS["rgb"], depth=TOPICS["depth"], camera_info=TOPICS["camera_info"], frame=None,
             world_frame=WORLD_FRAME, *, labels=None, classes=None, max_dt=DEFAULT_MAX_DT, min_range=None,
             max_range=None):
    """Reads a ROS 1 bag's RGB-D camera as canopy.Frame objects, for Map.insert and map_frames.

    Each depth image (depth: sensor_msgs/Image 16UC1 / mono16 millimetres or 32FC1 metres, NaN
    and 0 invalid, or a compressedDepth CompressedImage) makes a frame with
    - the RGB image (rgb: Image rgb8 / bgr8 / rgba8 / bgra8, or a jpeg / png CompressedImage;
      None for none), the label image (labels: Image mono8 / 8UC1 class indices, or rgb8 / bgr8
      class colours, canopy.class_colors; None for none) whose header stamps are nearest the
      depth's, within max_dt seconds, and the camera_info nearest it at any time (RGB and labels
      must be registered to the depth image: the same size and camera);
    - the pose T_world_camera of `frame` (default: the depth image's header frame_id, which
      must be the optical frame: x right, y down, z forward) in `world_frame`, from /tf and
      /tf_static at the depth's stamp: a sample at that stamp, else interpolated between the
      samples around it (linear, slerp), or the first / last sample when the stamp lies at most
      max_dt before / after it.
    The intrinsics come from camera_info (K; canopy puts pixel centres at +0.5, ROS at 0; the
    images must be rectified: a non-zero distortion is noted), the valid range from min_range and
    max_range (default: canopy.Intrinsics()'s).

    A missing topic or frame, a topic of another type, an unsupported encoding, header stamps out
    of order on an image topic, a frame not connected to world_frame by /tf and /tf_static, or
    a malformed transform raise BagError naming it. A depth image without partners within max_dt
    or without a transform at its stamp is skipped and listed.

    Returns {'frames': [canopy.Frame], 'skipped': [{'frame', 'reason'}], 'classes': [names],
    'notes': [str], 'stamps': [seconds of each frame]}.
    """
    path = os.fspath(path)
    if not (isinstance(max_dt, (int, float)) and math.isfinite(max_dt) and 0 < max_dt <= 10):
        raise BagError(f"max_dt: {max_dt!r} is not a time in (0, 10] s")
    defaults = _canopy.Intrinsics()
    min_range = defaults.min_range_m if min_range is None else float(min_range)
    max_range = defaults.max_range_m if max_range is None else float(max_range)
    class_names = list(classes) if classes is not None else list(DEFAULT_CLASSES)
    colors = _canopy.class_colors(class_names)
    max_dt_ns = int(round(max_dt * 1e9))

    bag = _open(path)
    try:
        topics = bag.get_type_and_topic_info().topics
        _check_topic(topics, path, depth, "depth", (IMAGE, COMPRESSED))
        _check_topic(topics, path, camera_info, "camera_info", (CAMERA_INFO,))
        if rgb is not None:
            _check_topic(topics, path, rgb, "rgb", (IMAGE, COMPRESSED))
        if labels is not None:
            _check_topic(topics, path, labels, "labels", (IMAGE,))
        tf_topics = [t for t in ("/tf", "/tf_static") if t in topics]
        for t in tf_topics:
            _check_topic(topics, path, t, "transforms", (TF_MESSAGE,))
        if not tf_topics:
            raise BagError(f"{path}: the bag has neither /tf nor /tf_static, so no camera pose")
        roles = {depth: "depth", camera_info: "camera_info"}
        if rgb is not None:
            roles[rgb] = "rgb"
        if labels is not None:
            roles[labels] = "labels"
        if len(roles) != 2 + (rgb is not None) + (labels is not None):
            raise BagError("rgb, depth, camera_info and labels must be different topics")
        tf = _Transforms(max_dt_ns)
        streams = {t: ([], []) for t in roles}  # topic -> ([stamp ns], [message])
        for topic, msg, _ in bag.read_messages(topics=list(roles) + tf_topics):
            if topic in ("/tf", "/tf_static"):
                for tfm in msg.transforms:
                    tf.add(tfm, topic, topic == "/tf_static")
                continue
            stamps, msgs = streams[topic]
            ns = _ns(msg.header.stamp)
            if topic == camera_info:  # paired by stamp whatever the order
                i = bisect.bisect_right(stamps, ns)
                stamps.insert(i, ns)
                msgs.insert(i, msg)
                continue
            if stamps and ns <= stamps[-1]:
                raise BagError(f"{topic}: header stamps out of order: message {len(stamps)} is stamped "
                               f"{_seconds(ns)}, not after the one before ({_seconds(stamps[-1])}); canopy pairs "
                               f"images by their stamps")
            stamps.append(ns)
            msgs.append(msg)
    finally:
        bag.close()

    depth_stamps, depth_msgs = streams[depth]
    if not depth_msgs:
        raise BagError(f"{path}: topic {depth} (depth) has no messages")
    if not streams[camera_info][1]:
        raise BagError(f"{path}: topic {camera_info} (camera_info) has no messages")
    source = frame if frame is not None else depth_msgs[0].header.frame_id.lstrip("/")
    if not source:
        raise BagError(f"{depth}: the depth images name no frame_id; give frame=")
    tf.check_path(source, world_frame)
    # Encodings are a topic's: the first message of each tells (before any pairing skips it).
    _depth(depth_msgs[0], depth)
    if rgb is not None and streams[rgb][1]:
        _rgb(streams[rgb][1][0], rgb)
    if labels is not None and streams[labels][1]:
        _labels(streams[labels][1][0], labels, colors)

    notes, frames, skipped, stamps = [], [], [], []
    distortion_noted = False
    for ns, dmsg in zip(depth_stamps, depth_msgs):
        name = f"{depth}@{ns / 1e9:.9f}"
        partners = {}
        why = None
        for topic, role in roles.items():
            if role == "depth":
                continue
            ts, ms = streams[topic]
            j = _nearest(ts, ns)
            if role == "camera_info":
                partners[role] = ms[j]
            elif j < 0 or abs(ts[j] - ns) > max_dt_ns:
                nearest = f"nearest {abs(ts[j] - ns) / 1e6:.1f} ms away" if j >= 0 else "none"
                why = f"no {role} image on {topic} within max_dt ({nearest})"
                break
            else:
                partners[role] = ms[j]
        if why is None:
            T = tf.lookup(world_frame, source, ns)
            if isinstance(T, str):
                why = T
        if why is not None:
            skipped.append({"frame": name, "reason": why})
            continue
        info = partners["camera_info"]
        if not distortion_noted and any(abs(float(v)) > 0 for v in info.D):
            notes.append(f"{camera_info}: distortion {list(info.D)} ignored: canopy takes rectified images")
            distortion_noted = True
        K = _intrinsics(info, camera_info, min_range, max_range)
        d, depth_scale = _depth(dmsg, depth)
        size = (K.height_px, K.width_px)
        arrays = {"depth": d}
        if "rgb" in partners:
            arrays["rgb"] = _rgb(partners["rgb"], rgb)
        if "labels" in partners:
            arrays["labels"] = _labels(partners["labels"], labels, colors)
        for role, a in arrays.items():
            if a.shape[:2] != size:
                topic = {"depth": depth, "rgb": rgb, "labels": labels}[role]
                raise BagError(f"{topic}: {role} image of {a.shape[1]} x {a.shape[0]} px, but camera_info says "
                               f"{size[1]} x {size[0]} (images must be registered to the depth camera)")
        frames.append(_canopy.Frame(arrays["depth"], T, K, labels=arrays.get("labels"), rgb=arrays.get("rgb"),
                                    depth_scale=depth_scale, name=name))
        stamps.append(ns / 1e9)
    return {"frames": frames, "skipped": skipped, "classes": class_names, "notes": notes, "stamps": stamps}


def map_bag(path, out, settings=None, *, rgb=TOPICS["rgb"], depth=TOPICS["depth"],
            camera_info=TOPICS["camera_info"], labels=None, frame=None, world_frame=WORLD_FRAME, classes=None,
            max_dt=DEFAULT_MAX_DT, min_range=None, max_range=None, progress=None):
    """Maps a bag's camera into the run folder `canopy map --frames` writes (canopy.map_frames):
    colour segmentation of the RGB images, or, with the settings' mapping.extractor.source
    truth, the label topic (`labels`, default /canopy/wrist/labels). Returns map_frames' dict."""
    s = settings if isinstance(settings, _canopy.Settings) else _canopy.Settings(settings)
    truth = s.get("mapping.extractor.source") == "truth"
    if truth and labels is None:
        labels = TOPICS["labels"]
    r = read_bag(path, rgb=None if truth else rgb, depth=depth, camera_info=camera_info, frame=frame,
                 world_frame=world_frame, labels=labels if truth else None, classes=classes, max_dt=max_dt,
                 min_range=min_range, max_range=max_range)
    if not r["frames"]:
        raise BagError(f"{path}: no frame could be mapped ({len(r['skipped'])} skipped; the first: "
                       f"{r['skipped'][0]['reason'] if r['skipped'] else 'none'})")
    run = {"command": "map-bag", "bag": os.path.abspath(path), "layout": "rosbag",
           "topics": {"rgb": None if truth else rgb, "depth": depth, "camera_info": camera_info,
                      "labels": labels if truth else None},
           "frame": frame or "", "world_frame": world_frame, "labels": "label topic" if truth else "color",
           "classes": r["classes"], "max_time_diff_s": float(max_dt)}
    return _canopy.map_frames(r["frames"], out, s, classes=r["classes"], run=run, skipped=r["skipped"],
                              notes=r["notes"], progress=progress)


# The writing half lives in bag_write.py (imported last: it uses the helpers above).
from .bag_write import export_bag, record_bag  # noqa: E402,F401
