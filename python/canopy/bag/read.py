"""Reading a ROS 1 bag's RGB-D camera (docs/real_robot.md#ros-bags).

BagReader reads a bag in two passes. The first reads the header stamps of the image topics,
camera_info and /tf, /tf_static (the image data is passed over), pairs each depth image with
its partners and its pose, and lists what it skips. The second, frames(), streams the image
topics once more and decodes one frame at a time, checking each image's declared size against
camera_info before decoding it: memory does not grow with the recording's length. map_bag
feeds frames() to canopy.map_frames; read_bag is list(frames()) (all frames in memory).
"""

import bisect
import io
import math
import os
import struct
import time

import numpy as np

from .. import _canopy
from .poses import TfTree
from .ros import (CAMERA_INFO, COMPRESSED, DEFAULT_CLASSES, DEFAULT_MAX_DT, IMAGE, TF_MESSAGE, TOPICS, WORLD_FRAME,
                  BagError, ns_of, ros, seconds, short)

DEPTH_ENCODINGS = "16UC1 or mono16 (millimetres), 32FC1 (metres)"
RGB_ENCODINGS = "rgb8, bgr8, rgba8, bgra8 or a jpeg / png CompressedImage"
LABEL_ENCODINGS = "mono8 or 8UC1 (class indices), rgb8 or bgr8 (class colours)"
# How many bytes of image messages the second pass may hold while a frame waits for a partner
# written later in the bag. A recording by `rosbag record` holds a few frames' worth (partners
# are received within milliseconds); a bag whose partners lie further apart is refused.
MAX_BUFFERED_BYTES = 1 << 30
# Seconds between progress lines while the first pass reads.
PROGRESS_PERIOD_S = 2.0

# std_msgs/Header at the start of every image message: seq, stamp (secs, nsecs), frame_id length.
_HEADER = struct.Struct("<IIII")


def _header(data, topic):
    """(stamp in ns, frame_id) of a serialized message that starts with a std_msgs/Header."""
    if len(data) < _HEADER.size:
        raise BagError(f"{topic}: a message of {len(data)} bytes is too short to hold a header")
    _, secs, nsecs, n = _HEADER.unpack_from(data, 0)
    if _HEADER.size + n > len(data) or n > 4096:
        raise BagError(f"{topic}: a message whose header's frame_id ({n} bytes) does not fit it")
    frame_id = bytes(data[_HEADER.size:_HEADER.size + n]).decode("utf-8", "replace")
    return secs * 1_000_000_000 + nsecs, frame_id


def _declared_size(data, datatype, topic, ns):
    """(width, height) an image message declares, read without decoding a pixel: an Image's
    width and height fields, a CompressedImage's image header (PIL reads the header only)."""
    _, _, _, n = _HEADER.unpack_from(data, 0)
    at = _HEADER.size + n
    try:
        if datatype == IMAGE:
            height, width = struct.unpack_from("<II", data, at)
            return width, height
        (n_format,) = struct.unpack_from("<I", data, at)
        fmt = bytes(data[at + 4:at + 4 + n_format]).decode("utf-8", "replace")
        at += 4 + n_format
        (n_data,) = struct.unpack_from("<I", data, at)
    except struct.error:
        raise BagError(f"{_where(topic, ns)}: a message too short for its fields") from None
    start = at + 4 + (12 if "compresseddepth" in fmt.lower().replace(" ", "") else 0)
    try:
        from PIL import Image as PILImage
    except ImportError:
        raise ImportError("compressed images need Debian's python3-pil (tools/deps.sh)") from None
    try:
        with PILImage.open(io.BytesIO(memoryview(data)[start:at + 4 + n_data])) as image:
            return image.size
    except Exception as e:
        raise BagError(f"{_where(topic, ns)}: a CompressedImage ({short(fmt, 40)}) that cannot be decoded: "
                       f"{short(e)}") from None


def _deserialize(raw, topic):
    """A message from rosbag's raw tuple (datatype, data, md5sum, position, pytype)."""
    try:
        msg = raw[4]()
        msg.deserialize(raw[1])
        return msg
    except Exception as e:  # genpy raises its own errors for malformed data
        raise BagError(f"{topic}: a {raw[0]} message that cannot be read ({type(e).__name__}: {short(e)})") from None


def _open(path):
    rosmods = ros()
    if not os.path.isfile(path):
        raise BagError(f"{path}: no such file")
    try:
        return rosmods.rosbag.Bag(path, "r")
    except Exception as e:  # rosbag raises its own exceptions and ValueError for what is no bag
        raise BagError(f"{path}: not a readable ROS 1 bag ({type(e).__name__}: {short(e)})") from None


def _check_topic(topics, path, topic, role, types_ok):
    if topic not in topics:
        listed = short(", ".join(sorted(topics)) or "none", 400)
        raise BagError(f"{path}: topic {topic} ({role}) is not in the bag (its topics: {listed})")
    kind = topics[topic].msg_type
    if kind not in types_ok:
        raise BagError(f"{path}: topic {topic} ({role}) is {kind}, not {' or '.join(types_ok)}")


def _check_encoding(msg, topic, role):
    """BagError unless canopy reads the encoding of `msg` (a topic's first message) as `role`;
    looks at the encoding or format only."""
    if role == "depth":
        if hasattr(msg, "encoding"):
            if msg.encoding not in ("16UC1", "mono16", "32FC1"):
                raise BagError(f"{topic}: depth encoding '{short(msg.encoding, 40)}' is not supported ({DEPTH_ENCODINGS})")
        else:
            fmt = msg.format.replace(" ", "")
            if "compresseddepth" not in fmt.lower():
                raise BagError(f"{topic}: CompressedImage format '{short(msg.format, 40)}' is not compressedDepth "
                               f"({DEPTH_ENCODINGS})")
            if not fmt.startswith(("16UC1", "32FC1")):
                raise BagError(f"{topic}: compressedDepth format '{short(msg.format, 40)}' is not supported "
                               f"({DEPTH_ENCODINGS})")
    elif role == "rgb":
        if hasattr(msg, "encoding") and msg.encoding not in ("rgb8", "bgr8", "rgba8", "bgra8"):
            raise BagError(f"{topic}: colour encoding '{short(msg.encoding, 40)}' is not supported ({RGB_ENCODINGS})")
    elif role == "labels":
        if msg.encoding not in ("mono8", "8UC1", "rgb8", "bgr8"):
            raise BagError(f"{topic}: label encoding '{short(msg.encoding, 40)}' is not supported ({LABEL_ENCODINGS})")


def _where(topic, ns):
    return f"{topic} at {seconds(ns)}"


def _check_size(width, height, K, topic, ns, role):
    """An image's declared size must be camera_info's (which canopy.Intrinsics caps): checked
    before any pixel is decoded."""
    if (int(width), int(height)) != (K.width_px, K.height_px):
        raise BagError(f"{_where(topic, ns)}: {role} image of {int(width)} x {int(height)} px, but camera_info says "
                       f"{K.width_px} x {K.height_px} (images must be registered to the depth camera)")


def _pixels(msg, topic, ns, dtype, channels):
    """A sensor_msgs/Image's pixels as an (H, W[, C]) array of `dtype` (row padding and byte order
    handled)."""
    item = np.dtype(dtype).newbyteorder(">" if msg.is_bigendian else "<")
    row = msg.width * channels * item.itemsize
    if msg.step < row or len(msg.data) < msg.step * msg.height:
        raise BagError(f"{_where(topic, ns)}: image data of {len(msg.data)} bytes with step {msg.step} does not hold "
                       f"{msg.height} rows of {msg.width} x {channels} {np.dtype(dtype).name}")
    raw = np.frombuffer(msg.data, dtype=np.uint8, count=msg.step * msg.height).reshape(msg.height, msg.step)
    a = np.ascontiguousarray(raw[:, :row]).view(item).astype(dtype, copy=False)
    return a.reshape(msg.height, msg.width, channels) if channels > 1 else a.reshape(msg.height, msg.width)


def _decode_compressed(msg, topic, ns, K, role):
    """A CompressedImage's pixels (a PIL image, loaded) after its declared size was checked."""
    try:
        from PIL import Image as PILImage
    except ImportError:
        raise ImportError("compressed images need Debian's python3-pil (tools/deps.sh)") from None
    data = bytes(msg.data)
    if "compresseddepth" in msg.format.lower().replace(" ", ""):
        data = data[12:]  # compressed_depth_image_transport's header: format and two quantisation floats
    try:
        image = PILImage.open(io.BytesIO(data))  # reads the header only
    except Exception as e:
        raise BagError(f"{_where(topic, ns)}: a CompressedImage ({short(msg.format, 40)}) that cannot be decoded: "
                       f"{short(e)}") from None
    _check_size(image.size[0], image.size[1], K, topic, ns, role)
    try:
        image.load()
    except Exception as e:
        raise BagError(f"{_where(topic, ns)}: a CompressedImage ({short(msg.format, 40)}) that cannot be decoded: "
                       f"{short(e)}") from None
    return image


def _depth(msg, topic, ns, K):
    """The depth image and its unit: (uint16 array, 0.001) for millimetres (as canopy.Frame and
    the frame folders' 16-bit PNGs scale them), or (float32 metres, None); 0 = invalid."""
    if hasattr(msg, "encoding"):
        _check_size(msg.width, msg.height, K, topic, ns, "depth")
        if msg.encoding in ("16UC1", "mono16"):
            return _pixels(msg, topic, ns, np.uint16, 1), 0.001
        d = _pixels(msg, topic, ns, np.float32, 1)
    else:
        fmt = msg.format.replace(" ", "")
        header = bytes(msg.data[:12])
        raw = np.asarray(_decode_compressed(msg, topic, ns, K, "depth"))
        if fmt.startswith("16UC1"):
            return raw.astype(np.uint16, copy=False), 0.001
        a, b = np.frombuffer(header[4:12].ljust(8, b"\0"), dtype="<f4")  # 32FC1: z = a / (v - b), quantised
        v = raw.astype(np.float32)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            d = np.where(v > 0, a / (v - b), 0).astype(np.float32)
    return np.where(np.isfinite(d) & (d > 0), d, 0).astype(np.float32), None


def _rgb(msg, topic, ns, K):
    if hasattr(msg, "encoding"):
        _check_size(msg.width, msg.height, K, topic, ns, "rgb")
        enc = msg.encoding
        a = _pixels(msg, topic, ns, np.uint8, 3) if enc in ("rgb8", "bgr8") else _pixels(msg, topic, ns, np.uint8, 4)[:, :, :3]
        return np.ascontiguousarray(a[:, :, ::-1] if enc.startswith("bgr") else a)
    image = _decode_compressed(msg, topic, ns, K, "rgb")
    return np.asarray(image if image.mode == "RGB" else image.convert("RGB"), dtype=np.uint8)


def _labels(msg, topic, ns, K, colors):
    _check_size(msg.width, msg.height, K, topic, ns, "labels")
    if msg.encoding in ("mono8", "8UC1"):
        ids = _pixels(msg, topic, ns, np.uint8, 1)
        if ids.size and int(ids.max()) >= len(colors):
            r, c = np.argwhere(ids >= len(colors))[0]
            raise BagError(f"{_where(topic, ns)}: pixel ({c}, {r}) has class {int(ids[r, c])}, but there are "
                           f"{len(colors)} classes")
        return ids
    rgb = _pixels(msg, topic, ns, np.uint8, 3)
    if msg.encoding == "bgr8":
        rgb = rgb[:, :, ::-1]
    try:  # the rule of `canopy map --frames` (datasets::ClassColorTable::decode)
        return _canopy.decode_class_colors(rgb, colors, _where(topic, ns))
    except ValueError as e:
        raise BagError(str(e)) from None


def _nearest(stamps, targets, max_dt_ns=None):
    """For each stamp of targets [ns], the index of the nearest of stamps [ns, non-decreasing]
    within max_dt_ns (None: any distance), else -1: datasets::nearest_timestamp's rule. Times go
    to the C++ as seconds from the first stamp, exact to well below a nanosecond's worth of
    tolerance."""
    if not stamps:
        return np.full(len(targets), -1, dtype=np.int64)
    origin = stamps[0]
    return _canopy.nearest_stamps([(t - origin) / 1e9 for t in stamps], [(t - origin) / 1e9 for t in targets],
                                  math.inf if max_dt_ns is None else max_dt_ns / 1e9)


class _Progress:
    """A progress callback called at most every PROGRESS_PERIOD_S seconds (and when forced)."""

    def __init__(self, progress):
        self.progress, self.last = progress, time.monotonic()

    def due(self):
        """True when a line is due now (the caller then makes it and calls this object)."""
        return self.progress is not None and time.monotonic() - self.last >= PROGRESS_PERIOD_S

    def __call__(self, line, force=False):
        if self.progress is not None and (force or self.due()):
            self.last = time.monotonic()
            self.progress(line)


class BagReader:
    """A ROS 1 bag's RGB-D camera as canopy.Frame objects, read without holding the recording.

    Constructing it reads the bag once (header stamps, camera_info, /tf, /tf_static; not the
    pixels) and plans the frames: len() of them, with `skipped`, `notes`, `classes`, `stamps`
    (seconds of each frame), `frame` (the camera frame the poses are of) and `names`. frames()
    reads the bag again and yields the frames one at a time, each image's declared size
    checked against camera_info (at most canopy.Intrinsics' 4096 px a side) before it is
    decoded. Arguments and errors: read_bag's.
    """

    def __init__(self, path, rgb=TOPICS["rgb"], depth=TOPICS["depth"], camera_info=TOPICS["camera_info"],
                 frame=None, world_frame=WORLD_FRAME, *, labels=None, classes=None, max_dt=DEFAULT_MAX_DT,
                 min_range=None, max_range=None, override_frame=False, progress=None):
        self.path = os.fspath(path)
        if not (isinstance(max_dt, (int, float)) and math.isfinite(max_dt) and 0 < max_dt <= 10):
            raise BagError(f"max_dt: {max_dt!r} is not a time in (0, 10] s")
        defaults = _canopy.Intrinsics()
        self._min_range = defaults.min_range_m if min_range is None else float(min_range)
        self._max_range = defaults.max_range_m if max_range is None else float(max_range)
        self.classes = list(classes) if classes is not None else list(DEFAULT_CLASSES)
        self._colors = _canopy.class_colors(self.classes)
        self._topics = {"depth": depth, "camera_info": camera_info, "rgb": rgb, "labels": labels}
        self.world_frame = world_frame
        self._progress = _Progress(progress)
        self.notes, self.skipped = [], []
        streams = self._first_pass(int(round(max_dt * 1e9)))
        self._plan_frames(streams, frame, override_frame, int(round(max_dt * 1e9)))

    # -- the first pass ---------------------------------------------------------------------

    def _first_pass(self, max_dt_ns):
        """Stamps (and bag order) of every image message, the camera_infos and the transforms."""
        path, t = self.path, self._topics
        bag = _open(path)
        try:
            topics = bag.get_type_and_topic_info().topics
            _check_topic(topics, path, t["depth"], "depth", (IMAGE, COMPRESSED))
            _check_topic(topics, path, t["camera_info"], "camera_info", (CAMERA_INFO,))
            if t["rgb"] is not None:
                _check_topic(topics, path, t["rgb"], "rgb", (IMAGE, COMPRESSED))
            if t["labels"] is not None:
                _check_topic(topics, path, t["labels"], "labels", (IMAGE,))
            tf_topics = [x for x in ("/tf", "/tf_static") if x in topics]
            for x in tf_topics:
                _check_topic(topics, path, x, "transforms", (TF_MESSAGE,))
            if not tf_topics:
                raise BagError(f"{path}: the bag has neither /tf nor /tf_static, so no camera pose")
            self._roles = {topic: role for role, topic in t.items() if topic is not None}
            if len(self._roles) != sum(topic is not None for topic in t.values()):
                raise BagError("rgb, depth, camera_info and labels must be different topics")
            self.tf = TfTree(max_dt_ns)
            # Image topics: header stamps in bag order; camera_info: (stamp, key of its intrinsics).
            streams = {topic: [] for topic, role in self._roles.items() if role != "camera_info"}
            sizes = {topic: [] for topic in streams}  # (width, height) each image declares
            infos, self._info_keys = [], {}
            self._depth_frame_id = None
            total = sum(topics[x].message_count for x in list(self._roles) + tf_topics)
            done = 0
            for topic, raw, _ in bag.read_messages(topics=list(self._roles) + tf_topics, raw=True):
                done += 1
                if self._progress.due():
                    self._progress(f"reading {path}: {done} of {total} messages ({100 * done // max(total, 1)}%)")
                if topic in ("/tf", "/tf_static"):
                    for tfm in _deserialize(raw, topic).transforms:
                        self.tf.add(tfm, topic, topic == "/tf_static")
                    continue
                role = self._roles[topic]
                if role == "camera_info":
                    msg = _deserialize(raw, topic)
                    key = (int(msg.width), int(msg.height), tuple(float(v) for v in msg.K),
                           any(abs(float(v)) > 0 for v in msg.D))
                    if key[3] and not any(n.startswith(f"{topic}: distortion") for n in self.notes):
                        self.notes.append(f"{topic}: distortion {short(list(msg.D), 120)} ignored: canopy takes "
                                          f"rectified images")
                    ns = ns_of(msg.header.stamp)
                    idx = self._info_keys.setdefault(key, len(self._info_keys))
                    bisect.insort(infos, (ns, idx))
                    continue
                ns, frame_id = _header(raw[1], topic)
                stamps = streams[topic]
                if not stamps:
                    _check_encoding(_deserialize(raw, topic), topic, role)  # a topic's encoding: its first message's
                if role == "depth":
                    if self._depth_frame_id is None:
                        self._depth_frame_id = frame_id.lstrip("/")
                    elif frame_id.lstrip("/") != self._depth_frame_id:
                        raise BagError(f"{topic}: the depth images name two frames, '{self._depth_frame_id}' (the "
                                       f"first) and '{short(frame_id, 60)}' (at {seconds(ns)}); canopy takes one camera")
                if stamps and ns <= stamps[-1]:
                    raise BagError(f"{topic}: header stamps out of order: message {len(stamps)} is stamped "
                                   f"{seconds(ns)}, not after the one before ({seconds(stamps[-1])}); canopy pairs "
                                   f"images by their stamps")
                stamps.append(ns)
                sizes[topic].append(_declared_size(raw[1], raw[0], topic, ns))
        finally:
            bag.close()
        if not streams[t["depth"]]:
            raise BagError(f"{path}: topic {t['depth']} (depth) has no messages")
        if not infos:
            raise BagError(f"{path}: topic {t['camera_info']} (camera_info) has no messages")
        streams[t["camera_info"]] = infos
        self._sizes = sizes
        return streams

    def _intrinsics(self, idx):
        width, height, K, _ = next(k for k, i in self._info_keys.items() if i == idx)
        topic = self._topics["camera_info"]
        if K[0] <= 0 or K[4] <= 0:
            raise BagError(f"{topic}: camera_info K has no focal lengths (fx {K[0]:g}, fy {K[4]:g})")
        try:  # ROS puts pixel centres at integer coordinates, canopy at +0.5
            return _canopy.Intrinsics(width, height, K[0], K[4], K[2] + 0.5, K[5] + 0.5, self._min_range,
                                      self._max_range)
        except ValueError as e:
            raise BagError(f"{topic}: {short(e)}") from None

    def _plan_frames(self, streams, frame, override_frame, max_dt_ns):
        t = self._topics
        depth = t["depth"]
        header_frame = self._depth_frame_id or ""
        if frame is None:
            if not header_frame:
                raise BagError(f"{depth}: the depth images name no frame_id; give frame= (--frame)")
            source = header_frame
        else:
            source = frame.lstrip("/")
            if header_frame and source != header_frame:
                if not override_frame:
                    raise BagError(f"frame '{source}' is not the depth images' frame '{header_frame}' (their header "
                                   f"frame_id, the optical frame their pixels are in); give that frame, or "
                                   f"override_frame=True (--override-frame) when their frame_id is wrong")
                self.notes.append(f"{depth}: poses of frame '{source}' (given) instead of the images' frame_id "
                                  f"'{header_frame}'")
                self._progress(f"warning: {self.notes[-1]}; '{source}' must be the optical frame (x right, y down, "
                               f"z forward)", force=True)
        self.frame = source
        self.tf.check_path(source, self.world_frame)
        intrinsics = {}
        info_stamps = [ns for ns, _ in streams[t["camera_info"]]]
        depth_stamps = streams[depth]
        info_of = _nearest(info_stamps, depth_stamps)
        paired, nearest = {}, {}  # per role: within max_dt, and at any distance (for the message)
        for role in ("rgb", "labels"):
            if t[role] is not None:
                paired[role] = _nearest(streams[t[role]], depth_stamps, max_dt_ns)
                nearest[role] = _nearest(streams[t[role]], depth_stamps)
        self._plan, self.stamps, self.names = [], [], []
        for k, ns in enumerate(depth_stamps):
            name = f"{depth}@{ns / 1e9:.9f}"
            refs, why = {"depth": k}, None
            for role in ("rgb", "labels"):
                topic = t[role]
                if topic is None:
                    continue
                j = int(paired[role][k])
                if j < 0:
                    n = int(nearest[role][k])
                    away = f"nearest {abs(streams[topic][n] - ns) / 1e6:.1f} ms away" if n >= 0 else "none"
                    why = f"no {role} image on {topic} within max_dt ({away})"
                    break
                refs[role] = j
            T = why if why is not None else self.tf.lookup(self.world_frame, source, ns)
            if isinstance(T, str):
                self.skipped.append({"frame": name, "reason": T})
                continue
            idx = streams[t["camera_info"]][int(info_of[k])][1]
            if idx not in intrinsics:
                intrinsics[idx] = self._intrinsics(idx)
            K = intrinsics[idx]
            for role, j in refs.items():  # before any pixel is decoded
                _check_size(*self._sizes[t[role]][j], K, t[role], streams[t[role]][j], role)
            self._plan.append((name, ns, refs, K, T))
            self.stamps.append(ns / 1e9)
            self.names.append(name)
        self._streams = streams

    def __len__(self):
        return len(self._plan)

    # -- the second pass ----------------------------------------------------------------------

    def frames(self):
        """Yields the planned frames in order, one at a time (the bag is read once more)."""
        t = self._topics
        image_topics = [t[r] for r in ("depth", "rgb", "labels") if t[r] is not None]
        waiting = {}  # (topic, index) -> how many planned frames still take that message
        for _, _, refs, _, _ in self._plan:
            for role, i in refs.items():
                waiting[(t[role], i)] = waiting.get((t[role], i), 0) + 1
        held, held_bytes = {}, 0  # (topic, index) -> raw message
        counters = {topic: 0 for topic in image_topics}
        next_frame = 0
        if not self._plan:
            return
        bag = _open(self.path)
        try:
            for topic, raw, _ in bag.read_messages(topics=image_topics, raw=True):
                i = counters[topic]
                counters[topic] += 1
                if (topic, i) not in waiting:
                    continue
                ns, _ = _header(raw[1], topic)
                if i >= len(self._streams[topic]) or self._streams[topic][i] != ns:
                    raise BagError(f"{topic}: message {i} is not the one read before ({seconds(ns)}); did the bag "
                                   f"change while it was read?")
                held[(topic, i)] = raw
                held_bytes += len(raw[1])
                while next_frame < len(self._plan) and all((t[r], j) in held for r, j in self._plan[next_frame][2].items()):
                    name, ns, refs, K, T = self._plan[next_frame]
                    msgs = {}
                    for role, j in refs.items():
                        key = (t[role], j)
                        msgs[role] = _deserialize(held[key], t[role])
                        waiting[key] -= 1
                        if waiting[key] == 0:
                            held_bytes -= len(held.pop(key)[1])
                            del waiting[key]
                    next_frame += 1
                    yield self._frame(name, ns, msgs, K, T)
                    msgs = None
                if next_frame == len(self._plan):
                    break  # the rest of the bag holds no planned frame's message
                if held_bytes > MAX_BUFFERED_BYTES:
                    name = self._plan[next_frame][0]
                    raise BagError(f"{self.path}: the messages of frame {name} lie more than "
                                   f"{MAX_BUFFERED_BYTES >> 20} MiB of images apart in the bag; canopy reads a bag in "
                                   f"one pass (reorder it by time: rosbag filter or rosbag reindex)")
        finally:
            bag.close()
        if next_frame < len(self._plan):
            raise BagError(f"{self.path}: frame {self._plan[next_frame][0]}'s messages were not found again; did the "
                           f"bag change while it was read?")

    def _frame(self, name, ns, msgs, K, T):
        t = self._topics
        arrays = {}
        for role, decode in (("depth", lambda m: _depth(m, t["depth"], ns, K)),
                             ("rgb", lambda m: _rgb(m, t["rgb"], ns, K)),
                             ("labels", lambda m: _labels(m, t["labels"], ns, K, self._colors))):
            if role not in msgs:
                continue
            try:
                arrays[role] = decode(msgs[role])
            except (BagError, MemoryError, ImportError):
                raise
            except Exception as e:  # whatever else a malformed message raises: named, on one line
                raise BagError(f"{_where(t[role], ns)}: {type(e).__name__}: {short(e)}") from None
        d, depth_scale = arrays["depth"]
        rgb, labels = arrays.get("rgb"), arrays.get("labels")
        try:
            return _canopy.Frame(d, T, K, labels=labels, rgb=rgb, depth_scale=depth_scale, name=name)
        except ValueError as e:
            raise BagError(f"{_where(t['depth'], ns)}: {short(e)}") from None


def read_bag(path, rgb=TOPICS["rgb"], depth=TOPICS["depth"], camera_info=TOPICS["camera_info"], frame=None,
             world_frame=WORLD_FRAME, *, labels=None, classes=None, max_dt=DEFAULT_MAX_DT, min_range=None,
             max_range=None, override_frame=False):
    """Reads a ROS 1 bag's RGB-D camera as canopy.Frame objects, for Map.insert and map_frames.
    Every frame is held in memory: map_bag, or BagReader(...).frames(), stream them instead.

    Each depth image (depth: sensor_msgs/Image 16UC1 / mono16 millimetres or 32FC1 metres, NaN
    and 0 invalid, or a compressedDepth CompressedImage) makes a frame with
    - the RGB image (rgb: Image rgb8 / bgr8 / rgba8 / bgra8, or a jpeg / png CompressedImage;
      None for none), the label image (labels: Image mono8 / 8UC1 class indices, or rgb8 / bgr8
      class colours, canopy.class_colors; None for none) whose header stamps are nearest the
      depth's, within max_dt seconds, and the camera_info nearest it at any time (RGB and labels
      must be registered to the depth image: the same size and camera);
    - the pose T_world_camera of `frame` in `world_frame`, from /tf and /tf_static at the depth's
      stamp: a sample at that stamp, else interpolated between the samples around it (linear,
      slerp), or the first / last sample when the stamp lies at most max_dt before / after it.
      `frame` defaults to the depth images' header frame_id, which must be the optical frame
      (x right, y down, z forward); another frame is refused unless override_frame=True (for a
      recording whose frame_id is wrong; noted).
    The intrinsics come from camera_info (K; canopy puts pixel centres at +0.5, ROS at 0; the
    images must be rectified: a non-zero distortion is noted), the valid range from min_range and
    max_range (default: canopy.Intrinsics()'s).

    A missing topic or frame, a topic of another type, an unsupported encoding, header stamps out
    of order on an image topic, an image whose size is not camera_info's, a frame not connected
    to world_frame by /tf and /tf_static, or a malformed transform raise BagError naming it. A
    depth image without partners within max_dt or without a transform at its stamp is skipped
    and listed.

    Returns {'frames': [canopy.Frame], 'skipped': [{'frame', 'reason'}], 'classes': [names],
    'notes': [str], 'stamps': [seconds of each frame], 'frame': the camera frame}.
    """
    r = BagReader(path, rgb, depth, camera_info, frame, world_frame, labels=labels, classes=classes, max_dt=max_dt,
                  min_range=min_range, max_range=max_range, override_frame=override_frame)
    return {"frames": list(r.frames()), "skipped": r.skipped, "classes": r.classes, "notes": r.notes,
            "stamps": r.stamps, "frame": r.frame}


def map_bag(path, out, settings=None, *, rgb=TOPICS["rgb"], depth=TOPICS["depth"],
            camera_info=TOPICS["camera_info"], labels=None, frame=None, world_frame=WORLD_FRAME, classes=None,
            max_dt=DEFAULT_MAX_DT, min_range=None, max_range=None, p_gt=None, override_frame=False, progress=None):
    """Maps a bag's camera into the run folder `canopy map --frames` writes (canopy.map_frames),
    streaming it (memory does not grow with the recording's length): colour segmentation of the
    RGB images, or, with the settings' mapping.extractor.source truth, the label topic
    (`labels`, default /canopy/wrist/labels). A recording's labels are taken as they are: p_gt
    (the probability a mask keeps its class; simulated mask noise) is 1 unless given, whatever
    the settings say. run.yaml records the bag, its topics and the camera frame used. Ctrl-C
    (KeyboardInterrupt) publishes the frames mapped so far, marked incomplete. Returns
    map_frames' dict."""
    s = settings.copy() if isinstance(settings, _canopy.Settings) else _canopy.Settings(settings)
    _canopy._check_output(out, "out", "map")  # before the bag is read
    s.set("mapping.extractor.p_gt", 1.0 if p_gt is None else p_gt)
    truth = s.get("mapping.extractor.source") == "truth"
    if truth and labels is None:
        labels = TOPICS["labels"]
    r = BagReader(path, rgb=None if truth else rgb, depth=depth, camera_info=camera_info, frame=frame,
                  world_frame=world_frame, labels=labels if truth else None, classes=classes, max_dt=max_dt,
                  min_range=min_range, max_range=max_range, override_frame=override_frame, progress=progress)
    if not len(r):
        raise BagError(f"{r.path}: no frame could be mapped ({len(r.skipped)} skipped; the first: "
                       f"{r.skipped[0]['reason'] if r.skipped else 'none'})")
    noise = "no simulated mask noise (p_gt 1; --pgt adds it)" if p_gt is None or p_gt == 1 else \
        f"simulated mask noise p_gt {p_gt:g}"
    if progress is not None:
        progress(f"read {r.path}: mapping {len(r)} frames ({len(r.skipped)} skipped), camera frame '{r.frame}', "
                 f"labels {'from ' + labels if truth else 'by colour segmentation of ' + rgb}: {noise}")
    run = {"command": "map-bag", "bag": os.path.abspath(r.path), "layout": "rosbag",
           "topics": {"rgb": None if truth else rgb, "depth": depth, "camera_info": camera_info,
                      "labels": labels if truth else None},
           "frame": r.frame, "world_frame": world_frame, "labels": "label topic" if truth else "color",
           "p_gt": float(s.get("mapping.extractor.p_gt")), "classes": r.classes, "max_time_diff_s": float(max_dt)}
    return _canopy.map_frames(r.frames(), out, s, count=len(r), classes=r.classes, run=run, skipped=r.skipped,
                              notes=r.notes, progress=progress)
