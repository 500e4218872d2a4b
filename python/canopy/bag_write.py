"""Writing ROS 1 bags (the writing half of canopy.bag): record_bag writes a mission as a bag while
it runs, export_bag writes a run folder's mission, replayed from its own records. The topics,
frames and message helpers are canopy.bag's; canopy.bag re-exports both calls."""

import json
import os
import pathlib
import tempfile

import numpy as np

from . import _canopy
from .bag import (FRUSTUM_DEPTH_M, PHASE_COLORS, TOPICS, WORLD_FRAME, BagError, _inverse, _matrix,
                  _quat_from_matrix, _ros)

# ----------------------------------------------------------------------------------

def _time(ros, ns):
    return ros.genpy.Time(ns // 1_000_000_000, ns % 1_000_000_000)


class _RunWriter:
    """Writes a mission into an open bag from run_mission's on_view and on_state."""

    def __init__(self, ros, bag, world):
        self.ros, self.bag, self.world = ros, bag, world
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
            T = _inverse(composed[parent]) @ world[name] if name == cam else _inverse(world[parent]) @ world[name]
            q = _quat_from_matrix(T[:3, :3])
            tfm = self.ros.geometry.TransformStamped()
            tfm.header = self._header(ns, parent)
            tfm.child_frame_id = name
            tfm.transform.translation.x, tfm.transform.translation.y, tfm.transform.translation.z = map(float, T[:3, 3])
            tfm.transform.rotation.x, tfm.transform.rotation.y, tfm.transform.rotation.z, tfm.transform.rotation.w = \
                map(float, q)
            msg.transforms.append(tfm)
            composed[name] = composed[parent] @ _matrix(T[:3, 3], q)  # as a reader composes it
        self.bag.write("/tf", msg, _time(self.ros, ns))

    def state(self, state):
        ns = int(round(state["time"] * 1e9))
        self._fruits(ns)
        self._tf(state, ns)

    def view(self, view):
        ns = int(round(view["time"] * 1e9))
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


def _check_bag_path(path):
    path = pathlib.Path(os.fspath(path))
    if path.is_dir():
        raise BagError(f"{path}: is a folder, not a bag file name")
    if not path.parent.is_dir():
        raise BagError(f"{path}: its folder {path.parent} does not exist")
    if path.suffix != ".bag":
        raise BagError(f"{path}: a ROS bag's name ends in .bag")
    return path


def record_bag(world, path, settings=None, *, state_period=0.1, **mission):
    """Runs the mission (canopy.run_mission(world, settings, **mission): method, planner, seed,
    out, video, progress) and writes it as a ROS 1 bag at `path` while it runs (published when the
    mission ends: the bag appears whole or not at all). /tf carries every link of the robot every
    state_period seconds of simulated time and at each view; header stamps are simulated time.
    Returns the MissionResult."""
    ros = _ros()
    path = _check_bag_path(path)
    fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".partial", dir=path.parent)
    os.close(fd)
    try:
        bag = ros.rosbag.Bag(tmp, "w", compression="lz4")
        try:
            writer = _RunWriter(ros, bag, world)
            result = _canopy.run_mission(world, settings, on_view=writer.view, on_state=writer.state,
                                         state_period=state_period, **mission)
        finally:
            bag.close()
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # as a file opened for writing would be (mkstemp makes it 0600)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return result


def export_bag(run_dir, path, *, progress=None):
    """The bag of a `canopy mission` run folder: the run is replayed from its own records (its
    settings.yaml, the world's resolved spec and the seed in summary.json; a mission is the same
    for a seed) and written with record_bag. Refused (BagError, no bag written) unless the
    replay's views.csv equals the run's byte for byte. Returns the MissionResult."""
    run = pathlib.Path(os.fspath(run_dir))
    for name in ("summary.json", "settings.yaml", "views.csv"):
        if not (run / name).is_file():
            raise BagError(f"{run}: not a canopy mission run folder (no {name})")
    summary = json.loads((run / "summary.json").read_text())
    method = summary.get("method", {})
    method_name = method.get("name") if isinstance(method, dict) else method
    if method_name == "python":
        raise BagError(f"{run}: the run was planned by a Python planner, which its folder does not hold; write its "
                       f"bag while it runs: canopy.record_bag(world, path, planner=...)")
    if summary.get("complete") is False:
        raise BagError(f"{run}: the run was interrupted (summary.json \"complete\": false); only a whole run replays")
    spec = (summary.get("world") or {}).get("spec") if isinstance(summary.get("world"), dict) else None
    if spec is None or "seed" not in summary:
        raise BagError(f"{run}: summary.json lacks the world's resolved spec or the seed")
    path = _check_bag_path(path)
    replay = path.with_name(f".{path.name}.replay.bag")  # beside the bag: published by a rename
    try:
        with tempfile.TemporaryDirectory(prefix="canopy-export-bag.") as tmp:
            world_file = pathlib.Path(tmp) / "world.json"
            world_file.write_text(json.dumps(spec))
            world = _canopy.World(str(world_file))
            settings = _canopy.Settings(str(run / "settings.yaml"))
            result = record_bag(world, replay, settings, seed=int(summary["seed"]), progress=progress)
        recorded = (run / "views.csv").read_text()
        if result.views_csv != recorded:
            a, b = result.views_csv.splitlines(), recorded.splitlines()
            line = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
            raise BagError(f"{run}: replaying the run gave other views than its views.csv (first difference on line "
                           f"{line + 1}); was it made by another canopy? No bag written")
        os.replace(replay, path)
    finally:
        if replay.exists():
            replay.unlink()
    return result
