"""Poses in bags: 4x4 transforms and quaternions, and the transform tree of a bag's /tf and
/tf_static (TfTree: lookups at a stamp, interpolated as tf2 does)."""

import bisect
import math

import numpy as np

from .ros import BagError, ns_of, seconds, short


def quat_from_matrix(R):
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


def matrix(t, q):
    """4x4 transform from a translation and a unit quaternion (x, y, z, w)."""
    x, y, z, w = q
    T = np.eye(4)
    T[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    T[:3, 3] = t
    return T


def inverse(T):
    """Inverse of a rigid 4x4 transform."""
    out = np.eye(4)
    out[:3, :3] = T[:3, :3].T
    out[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return out


def slerp(q0, q1, s):
    """Spherical interpolation of unit quaternions, s in [0, 1]."""
    d = float(np.dot(q0, q1))
    if d < 0.0:
        q1, d = -q1, -d
    if d > 0.9995:
        q = q0 + s * (q1 - q0)
    else:
        a = math.acos(d)
        q = (math.sin((1 - s) * a) * q0 + math.sin(s * a) * q1) / math.sin(a)
    return q / np.linalg.norm(q)


class TfTree:
    """A bag's /tf and /tf_static: one parent per frame, time-stamped samples of the dynamic
    edges (sorted by stamp; at equal stamps the later message wins)."""

    def __init__(self, max_dt_ns):
        self.parent = {}       # child -> parent
        self.static = {}       # child -> 4x4
        self.samples = {}      # child -> ([stamps], [(t, q)])
        self.max_dt_ns = max_dt_ns

    def add(self, tfm, topic, is_static):
        """Adds one geometry_msgs/TransformStamped of `topic`; BagError when it is malformed."""
        child, parent = tfm.child_frame_id.lstrip("/"), tfm.header.frame_id.lstrip("/")
        if not child or not parent:
            raise BagError(f"{topic}: a transform with an empty frame name ('{short(parent, 60)}' -> "
                           f"'{short(child, 60)}')")
        known = self.parent.get(child)
        if known is not None and known != parent:
            raise BagError(f"{topic}: frame '{child}' has two parents, '{known}' and '{parent}' (a tf tree has one)")
        self.parent[child] = parent
        r, p = tfm.transform.rotation, tfm.transform.translation
        q = np.array([r.x, r.y, r.z, r.w], dtype=float)
        n = float(np.linalg.norm(q))
        if not (abs(n - 1.0) < 1e-3) or not np.all(np.isfinite([p.x, p.y, p.z])):
            raise BagError(f"{topic}: transform '{parent}' -> '{child}' at {seconds(ns_of(tfm.header.stamp))} is not a "
                           f"rigid transform (quaternion norm {n:.6g}, translation {p.x:.6g}, {p.y:.6g}, {p.z:.6g})")
        t = np.array([p.x, p.y, p.z], dtype=float)
        q = q / n
        if is_static:
            if child in self.samples:
                raise BagError(f"{topic}: frame '{child}' is both in /tf and /tf_static")
            self.static[child] = matrix(t, q)
            return
        if child in self.static:
            raise BagError(f"{topic}: frame '{child}' is both in /tf and /tf_static")
        stamps, values = self.samples.setdefault(child, ([], []))
        ns = ns_of(tfm.header.stamp)
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
                listed = short(", ".join(self.frames()) or "none", 300)
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
            return matrix(*values[i])
        edge = f"'{self.parent[child]}' -> '{child}'"
        if i == 0 or i == len(stamps):
            j = 0 if i == 0 else len(stamps) - 1
            if abs(stamps[j] - ns) <= self.max_dt_ns:
                return matrix(*values[j])
            side = "before the first" if i == 0 else "after the last"
            return f"no /tf {edge} at {seconds(ns)} ({side} sample, {seconds(stamps[j])}, by more than max_dt)"
        (t0, q0), (t1, q1) = values[i - 1], values[i]
        s = (ns - stamps[i - 1]) / (stamps[i] - stamps[i - 1])
        return matrix(t0 + s * (t1 - t0), slerp(q0, q1, s))

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
        return inverse(T_common_target) @ T_common_source
