"""Writing ROS 1 bags: record_bag writes a mission as a bag while it runs, export_bag writes a
`canopy mission` run folder's mission, replayed from its own records (docs/real_robot.md#ros-bags).

A bag is written as `.NAME.partial` beside NAME (canopy's own name, locked while it is written:
one left by a killed run is overwritten by the next) and renamed to NAME when complete: NAME is
the whole bag or absent. An interrupted or failed write leaves nothing. NAME is never inside a
canopy output folder (that command's next run replaces the folder whole), and an existing NAME
is replaced only when canopy wrote it (is_canopy_bag: the marker topic WRITER_TOPIC with
WRITER_FIELD in its connection header)."""

import contextlib
import errno
import fcntl
import json
import os
import pathlib
import signal
import stat
import tempfile

import numpy as np

from .. import _canopy
from .poses import inverse, matrix, quat_from_matrix
from .ros import TOPICS, WORLD_FRAME, WRITER_FIELD, WRITER_TOPIC, BagError, ros



def _phase_colors():
    """RGBA of the view frustums by phase: canopy's one table of phase colours (records.h,
    view_colour), the colours the report draws its cameras in."""
    def rgba(hex_colour):
        v = int(hex_colour[1:], 16)
        return ((v >> 16 & 255) / 255.0, (v >> 8 & 255) / 255.0, (v & 255) / 255.0, 1.0)
    return {p["name"]: rgba(p["colour"]) for p in _canopy.vocabulary()["view_phases"]}


PHASE_COLORS = _phase_colors()
# The fields of each view's record on TOPICS["view_record"] (std_msgs/String, JSON): the views'
# schema (canopy.view_fields(), views.csv's and the report's names) known when the view is taken.
VIEW_RECORD_FIELDS = tuple(f["name"] for f in _canopy.view_fields() if f["known_when_taken"])
FRUSTUM_DEPTH_M = 0.1


def _plain(value):
    """A value of on_view's dict as JSON: arrays as (nested) lists, NumPy scalars as numbers."""
    return value.tolist() if isinstance(value, (np.ndarray, np.generic)) else value


def view_record_json(view):
    """The record of one view as the bag holds it: on_view's fields of the views' schema."""
    return json.dumps({name: _plain(view[name]) for name in VIEW_RECORD_FIELDS}, sort_keys=False)


def _time(rosmods, ns):
    return rosmods.genpy.Time(ns // 1_000_000_000, ns % 1_000_000_000)


def _write_error(path, e):
    """An OSError of writing the bag at `path` as one line naming the file (and a full disk)."""
    if e.errno in (errno.ENOSPC, errno.EDQUOT):
        why = f"the disk is full ({os.strerror(e.errno)})"
    elif e.errno == errno.EFBIG:
        why = f"the file size limit is reached ({os.strerror(e.errno)}; ulimit -f)"
    else:
        why = os.strerror(e.errno) if e.errno else " ".join(str(e).split())
    err = OSError(f"{path}: cannot write the bag: {why}; no bag written")
    err.errno = e.errno
    return err


class _RunWriter:
    """Writes a mission into an open bag from run_mission's on_view and on_state."""

    def __init__(self, rosmods, bag, world, path):
        self.ros, self.bag, self.world, self.path = rosmods, bag, world, path
        self.failed = False  # a hook raised: the bag is discarded, and nothing more is written
        self.last_ns = 0
        self.classes = list(world.classes)
        self.colors = _canopy.class_colors(self.classes)
        self.K = world.camera
        self.views = []  # (phase, pose) of every successful view so far
        self.fruits_written = False

    def _header(self, ns, frame_id):
        h = self.ros.std.Header()
        h.stamp = _time(self.ros, ns)
        h.frame_id = frame_id
        return h

    def _tf(self, state, ns, camera_pose=None):
        """/tf of every link (its parent's frame), and of the camera so that its chain gives
        `camera_pose` (the pose the frame was mapped with)."""
        world = {WORLD_FRAME: np.eye(4)}
        for name, pose in zip(state["links"], state["link_poses"]):
            world[name] = np.asarray(pose)
        cam = state["camera_frame"]
        if camera_pose is not None and cam in world:
            world[cam] = np.asarray(camera_pose)
        msg = self.ros.tf2.TFMessage()
        composed = {WORLD_FRAME: np.eye(4)}
        for name, parent in zip(state["links"], state["parents"]):
            T = inverse(composed[parent]) @ world[name] if name == cam else inverse(world[parent]) @ world[name]
            q = quat_from_matrix(T[:3, :3])
            tfm = self.ros.geometry.TransformStamped()
            tfm.header = self._header(ns, parent)
            tfm.child_frame_id = name
            tfm.transform.translation.x, tfm.transform.translation.y, tfm.transform.translation.z = map(float, T[:3, 3])
            tfm.transform.rotation.x, tfm.transform.rotation.y, tfm.transform.rotation.z, tfm.transform.rotation.w = \
                map(float, q)
            msg.transforms.append(tfm)
            composed[name] = composed[parent] @ matrix(T[:3, 3], q)  # as a reader composes it
        self.bag.write("/tf", msg, _time(self.ros, ns))

    def _guarded(self, write, arg):
        """Runs a hook's writing; after any failure (a full disk, Ctrl-C) nothing more is written,
        and the bag is discarded when the mission returns."""
        if self.failed:
            return
        try:
            write(arg)
        except OSError as e:
            self.failed = True
            raise _write_error(self.path, e) from None
        except BaseException:
            self.failed = True
            raise

    def state(self, state):
        """run_mission's on_state."""
        self._guarded(self._state, state)

    def view(self, view):
        """run_mission's on_view."""
        self._guarded(self._view, view)

    def finish(self, kind):
        """Writes canopy's marker (is_canopy_bag) and closes the bag (its index)."""
        String = self.ros.std.String
        header = {"topic": WRITER_TOPIC, "type": String._type, "md5sum": String._md5sum,
                  "message_definition": String._full_text, WRITER_FIELD: kind}
        try:
            self.bag.write(WRITER_TOPIC, String(data=f"written by canopy {kind}"), _time(self.ros, self.last_ns),
                           connection_header=header)
            self.bag.close()
        except OSError as e:
            raise _write_error(self.path, e) from None

    def _state(self, state):
        ns = int(round(state["time"] * 1e9))
        self.last_ns = max(self.last_ns, ns)
        self._fruits(ns)
        self._tf(state, ns)

    def _view(self, view):
        ns = int(round(view["time"] * 1e9))
        self.last_ns = max(self.last_ns, ns)
        f = view["frame"]
        cam = view["camera_frame"]
        self._fruits(ns)
        self._tf(view, ns, camera_pose=f.pose)
        t = _time(self.ros, ns)
        h, w = f.depth.shape
        info = self.ros.sensor.CameraInfo()
        info.header = self._header(ns, cam)
        info.width, info.height = w, h
        K = f.intrinsics
        cx, cy = K.cx_px - 0.5, K.cy_px - 0.5  # ROS: pixel centres at integer coordinates
        info.distortion_model = "plumb_bob"
        info.D = [0.0] * 5
        info.K = [K.fx_px, 0.0, cx, 0.0, K.fy_px, cy, 0.0, 0.0, 1.0]
        info.R = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
        info.P = [K.fx_px, 0.0, cx, 0.0, 0.0, K.fy_px, cy, 0.0, 0.0, 0.0, 1.0, 0.0]
        self.bag.write(TOPICS["camera_info"], info, t)
        self.bag.write(TOPICS["rgb"], self._image(ns, cam, f.rgb, "rgb8"), t)
        self.bag.write(TOPICS["depth"], self._image(ns, cam, np.asarray(f.depth, dtype="<f4"), "32FC1"), t)
        if f.labels is not None:
            self.bag.write(TOPICS["labels"], self._image(ns, cam, f.labels, "mono8"), t)
            self.bag.write(TOPICS["labels_color"], self._image(ns, cam, self.colors[np.minimum(
                f.labels, len(self.colors) - 1)], "rgb8"), t)
        self.bag.write(TOPICS["map"], self._cloud(ns, view["map"]), t)
        self.views.append((view["phase"], f.pose, K))
        self.bag.write(TOPICS["views"], self._frustums(ns), t)
        self.bag.write(TOPICS["view_record"], self.ros.std.String(data=view_record_json(view)), t)

    def _image(self, ns, frame_id, a, encoding):
        a = np.ascontiguousarray(a)
        m = self.ros.sensor.Image()
        m.header = self._header(ns, frame_id)
        m.height, m.width = a.shape[:2]
        m.encoding = encoding
        m.is_bigendian = 0
        m.step = a.strides[0]
        m.data = a.tobytes()
        return m

    def _cloud(self, ns, map_):
        v = map_.voxels("occupied")
        n = len(v["center"])
        cls = np.asarray(v["most_likely_class"], dtype=np.int64)
        rgb = self.colors[np.clip(cls, 0, len(self.colors) - 1)].astype(np.uint32)
        packed = (rgb[:, 0] << 16) | (rgb[:, 1] << 8) | rgb[:, 2]
        point = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rgb", "<u4"), ("probability", "<f4"),
                          ("class", "u1"), ("pad", "u1", 3)])
        pts = np.zeros(n, dtype=point)
        c = np.asarray(v["center"])
        pts["x"], pts["y"], pts["z"] = c[:, 0], c[:, 1], c[:, 2]
        pts["rgb"] = packed
        pts["probability"] = v["p_occ"]
        pts["class"] = np.clip(cls, 0, 255)
        PF = self.ros.sensor.PointField
        m = self.ros.sensor.PointCloud2()
        m.header = self._header(ns, WORLD_FRAME)
        m.height, m.width = 1, n
        m.fields = [PF(name="x", offset=0, datatype=PF.FLOAT32, count=1),
                    PF(name="y", offset=4, datatype=PF.FLOAT32, count=1),
                    PF(name="z", offset=8, datatype=PF.FLOAT32, count=1),
                    PF(name="rgb", offset=12, datatype=PF.FLOAT32, count=1),  # packed 0x00RRGGBB, as RViz reads it
                    PF(name="probability", offset=16, datatype=PF.FLOAT32, count=1),
                    PF(name="class", offset=20, datatype=PF.UINT8, count=1)]
        m.is_bigendian = False
        m.point_step = point.itemsize
        m.row_step = point.itemsize * n
        m.is_dense = True
        m.data = pts.tobytes()
        return m

    def _marker(self, ns, ns_name, mid, kind, color):
        M = self.ros.viz.Marker
        m = M()
        m.header = self._header(ns, WORLD_FRAME)
        m.ns, m.id, m.type, m.action = ns_name, mid, kind, M.ADD
        m.pose.orientation.w = 1.0
        m.color.r, m.color.g, m.color.b, m.color.a = color
        return m

    def _frustums(self, ns):
        """Every successful view so far as a frustum (LINE_LIST), by phase (the marker namespace)."""
        out = self.ros.viz.MarkerArray()
        P = self.ros.geometry.Point
        for i, (phase, pose, K) in enumerate(self.views):
            m = self._marker(ns, phase, i, self.ros.viz.Marker.LINE_LIST, PHASE_COLORS.get(phase, (1, 1, 1, 1)))
            m.scale.x = 0.003 if i + 1 < len(self.views) else 0.008  # the newest view drawn thicker
            T, d = np.asarray(pose), FRUSTUM_DEPTH_M
            corners = [T[:3, :3] @ np.array([(u - K.cx_px) / K.fx_px * d, (v - K.cy_px) / K.fy_px * d, d]) + T[:3, 3]
                       for u, v in ((0, 0), (K.width_px, 0), (K.width_px, K.height_px), (0, K.height_px))]
            apex = T[:3, 3]
            for k in range(4):
                for a, b in ((apex, corners[k]), (corners[k], corners[(k + 1) % 4])):
                    m.points.append(P(*map(float, a)))
                    m.points.append(P(*map(float, b)))
            out.markers.append(m)
        return out

    def _fruits(self, ns):
        """The true fruits as boxes (red: target, yellow-green: the others), once at the start."""
        if self.fruits_written:
            return
        self.fruits_written = True
        f = self.world.fruits
        out = self.ros.viz.MarkerArray()
        for i in range(len(f["instance_id"])):
            lo, hi = np.asarray(f["bbox_min"][i]), np.asarray(f["bbox_max"][i])
            color = (0.9, 0.1, 0.1, 0.5) if f["target"][i] else (0.7, 0.8, 0.2, 0.5)
            m = self._marker(ns, "fruits", int(f["instance_id"][i]), self.ros.viz.Marker.CUBE, color)
            m.pose.position.x, m.pose.position.y, m.pose.position.z = map(float, (lo + hi) / 2)
            m.scale.x, m.scale.y, m.scale.z = map(float, np.maximum(hi - lo, 1e-3))
            out.markers.append(m)
        self.bag.write(TOPICS["fruits"], out, _time(self.ros, ns))


def is_canopy_bag(path):
    """True when the file at `path` is a bag canopy wrote (its marker: a WRITER_TOPIC message
    whose connection header holds WRITER_FIELD); False for anything else, a link or an
    unreadable file included."""
    try:
        if not stat.S_ISREG(os.lstat(path).st_mode):
            return False
        with ros().rosbag.Bag(os.fspath(path), "r") as b:
            if WRITER_TOPIC not in b.get_type_and_topic_info().topics:
                return False
            for m in b.read_messages(topics=[WRITER_TOPIC], return_connection_header=True):
                return WRITER_FIELD in m.connection_header or WRITER_FIELD.encode() in m.connection_header
    except Exception:  # not a bag, unindexed, unreadable: not canopy's
        return False
    return False


def _check_bag_path(path, option, others=()):
    """The bag's path, refused (BagError) unless canopy may write there: a name ending in .bag in
    an existing folder, not a link, not inside a canopy output folder nor inside `others` (the
    run's out and video), and either absent or a bag canopy wrote."""
    p = pathlib.Path(os.fspath(path))
    if p.suffix != ".bag":
        raise BagError(f"{p}: a ROS bag's name ends in .bag")
    if p.is_symlink():
        raise BagError(f"{p}: is a symbolic link; canopy does not write through it (remove it or choose another name)")
    if p.is_dir():
        raise BagError(f"{p}: is a folder, not a bag file name")
    if not p.parent.is_dir():
        raise BagError(f"{p}: its folder {p.parent} does not exist")
    try:
        _canopy._check_output(str(p), option)
        _canopy._check_disjoint_outputs([(str(p), option)] + [(str(o), name) for o, name in others if o is not None])
    except ValueError as e:
        raise BagError(str(e)) from None
    _check_replaceable(p)
    return p


def _check_replaceable(p):
    if os.path.lexists(p) and not is_canopy_bag(p):
        raise BagError(f"{p}: exists and is not a bag canopy wrote; canopy does not overwrite it (remove it or "
                       f"choose another name)")


@contextlib.contextmanager
def _signals_held():
    """SIGINT and SIGTERM wait (blocked) while the block runs; their handlers run after it."""
    held = {signal.SIGINT, signal.SIGTERM}
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


class _PartialBag:
    """The bag being written: `.NAME.partial` beside NAME, locked (flock) while written,
    published by a rename, removed on any failure."""

    def __init__(self, path, option, others=()):
        self.path = _check_bag_path(path, option, others)
        self.tmp = self.path.with_name(f".{self.path.name}.partial")
        for _ in range(10):
            try:  # never through a link; a FIFO planted in its place does not hang the open
                fd = os.open(self.tmp, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC | os.O_NONBLOCK, 0o666)
            except OSError as e:
                if e.errno == errno.ELOOP:
                    raise BagError(f"{self.tmp}: is a symbolic link, not canopy's partial bag; remove it") from None
                raise BagError(f"{self.path}: cannot write here: {os.strerror(e.errno)}") from None
            st = os.fstat(fd)
            if not stat.S_ISREG(st.st_mode):
                os.close(fd)
                raise BagError(f"{self.tmp}: is not a file, not canopy's partial bag; remove it")
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                raise BagError(f"{self.path}: is busy: another canopy is writing it now (try again when it has "
                               f"finished)") from None
            try:  # the holder before us may have published or removed the file we opened
                now = os.lstat(self.tmp)
            except FileNotFoundError:
                now = None
            if now is not None and (now.st_ino, now.st_dev) == (st.st_ino, st.st_dev):
                break
            os.close(fd)
        else:
            raise BagError(f"{self.tmp}: cannot be locked")
        self._lock_fd = fd
        self.published = False
        os.ftruncate(fd, 0)
        # rosbag closes the file it is given; the lock is held by our own descriptor until the
        # bag is published or removed.
        self.file = os.fdopen(os.dup(fd), "w+b")

    def publish(self):
        """Renames the complete bag into place (again refused when a file canopy did not write
        appeared there meanwhile). Ctrl-C and SIGTERM wait while it renames, so `published`
        says whether the bag is in place."""
        _check_replaceable(self.path)
        try:
            with _signals_held():
                os.replace(self.tmp, self.path)
                self.published = True
        except OSError as e:
            raise _write_error(self.path, e) from None
        self._close()

    def discard(self):
        """Removes the partial bag (whatever stopped the writing), unless it was published."""
        if not self.published and self._lock_fd is not None:
            try:
                os.unlink(self.tmp)
            except OSError:
                pass
        self._close()

    def interrupted_after_publishing(self, error):
        """KeyboardInterrupt saying the bag is whole, when `error` came after publish()."""
        if self.published and isinstance(error, KeyboardInterrupt):
            return KeyboardInterrupt(f"interrupted after {self.path} was written whole")
        return None

    def _close(self):
        try:
            self.file.close()  # after rosbag's own close, or with data a full disk refused
        except OSError:
            pass
        if self._lock_fd is not None:
            os.close(self._lock_fd)
            self._lock_fd = None


def _record(world, partial, settings, kind, state_period, mission):
    """Runs the mission writing its bag into `partial`; returns the MissionResult."""
    rosmods = ros()
    bag = rosmods.rosbag.Bag(partial.file, "w", compression="lz4")
    writer = _RunWriter(rosmods, bag, world, partial.path)
    result = _canopy.run_mission(world, settings, on_view=writer.view, on_state=writer.state,
                                 state_period=state_period, **mission)
    writer.finish(kind)
    return result


def record_bag(world, path, settings=None, *, state_period=0.1, **mission):
    """Runs the mission (canopy.run_mission(world, settings, **mission): method, planner, seed,
    out, video, progress) and writes it as a ROS 1 bag at `path` while it runs, published when the
    mission ends: the bag appears whole or not at all (an interrupted mission, Ctrl-C, leaves
    none; the out folder keeps what run_mission keeps). /tf carries every link of the robot every
    state_period seconds of simulated time and at each view; header stamps are simulated time.
    `path` is refused (BagError, before the mission) inside a canopy output folder or the run's
    out, and when a file canopy did not write is there. Returns the MissionResult."""
    partial = _PartialBag(path, "path", [(mission.get("out"), "out"), (mission.get("video"), "video")])
    try:
        result = _record(world, partial, settings, "record_bag", state_period, mission)
        partial.publish()
    except BaseException as e:
        partial.discard()
        raise partial.interrupted_after_publishing(e) or e
    return result


def export_bag(run_dir, path, *, progress=None):
    """The bag of a `canopy mission` run folder: the run is replayed from its own records (its
    settings.yaml, the world's resolved spec and the seed in summary.json; a mission is the same
    for a seed) and written as record_bag writes it. Refused (BagError, no bag written) unless the
    replay's views.csv equals the run's byte for byte, and where record_bag refuses the path.
    Returns the MissionResult."""
    run = pathlib.Path(os.fspath(run_dir))
    for name in ("summary.json", "settings.yaml", "views.csv"):
        if not (run / name).is_file():
            raise BagError(f"{run}: not a canopy mission run folder (no {name})")
    try:
        summary = json.loads((run / "summary.json").read_text())
    except ValueError as e:
        raise BagError(f"{run}/summary.json: not JSON ({' '.join(str(e).split())})") from None
    if not isinstance(summary, dict):
        raise BagError(f"{run}/summary.json: not a canopy summary (no JSON object)")
    method = summary.get("method", {})
    method_name = method.get("name") if isinstance(method, dict) else method
    if method_name == "python":
        raise BagError(f"{run}: the run was planned by a Python planner, which its folder does not hold; write its "
                       f"bag while it runs: canopy.record_bag(world, path, planner=...)")
    if summary.get("complete") is False:
        raise BagError(f"{run}: the run was interrupted (summary.json \"complete\": false); only a whole run replays")
    spec = (summary.get("world") or {}).get("spec") if isinstance(summary.get("world"), dict) else None
    if spec is None or not isinstance(summary.get("seed"), int):
        raise BagError(f"{run}: summary.json lacks the world's resolved spec or the seed")
    partial = _PartialBag(path, "bag")
    try:
        if progress is not None:
            progress(f"replaying {run} (seed {summary['seed']}) into {partial.path}")
        with tempfile.TemporaryDirectory(prefix="canopy-export-bag.") as tmp:
            world_file = pathlib.Path(tmp) / "world.json"
            world_file.write_text(json.dumps(spec))
            world = _canopy.World(str(world_file))
            settings = _canopy.Settings(str(run / "settings.yaml"))
            result = _record(world, partial, settings, "export-bag", 0.1,
                             {"seed": summary["seed"], "progress": progress})
        recorded = (run / "views.csv").read_text()
        if result.views_csv != recorded:
            a, b = result.views_csv.splitlines(), recorded.splitlines()
            line = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
            raise BagError(f"{run}: replaying the run gave other views than its views.csv (first difference on line "
                           f"{line + 1}); was it made by another canopy? No bag written")
        partial.publish()
    except BaseException as e:
        partial.discard()
        raise partial.interrupted_after_publishing(e) or e
    return result
