"""Shared fixtures of the Python tests (run by ctest: python.* with PYTHONPATH at the build's
python/ folder and CANOPY_CLI naming the canopy executable; docs/python.md)."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

import canopy

SOURCE = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def world():
    """The small world: one plant on each side of the aisle, one stop."""
    return canopy.World("worlds/small.yaml")


@pytest.fixture(scope="session")
def cli():
    """Runs the canopy executable ctest names (CANOPY_CLI); returns its completed process."""
    exe = os.environ.get("CANOPY_CLI")
    assert exe and os.path.exists(exe), "CANOPY_CLI must name the canopy executable (ctest sets it)"

    def run(*args):
        p = subprocess.run([exe, *map(str, args)], capture_output=True, text=True, cwd=SOURCE)
        assert p.returncode == 0, f"canopy {' '.join(map(str, args))}: exit {p.returncode}\n{p.stderr}"
        return p

    return run


def pose7(T):
    """x,y,z,qw,qx,qy,qz of a 4x4 pose (the command line's --camera-pose)."""
    R = T[:3, :3]
    w = np.sqrt(max(0.0, 1.0 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = np.copysign(np.sqrt(max(0.0, 1.0 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1.0 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1.0 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    q = np.array([w, x, y, z]) / np.linalg.norm([w, x, y, z])
    return ",".join(repr(float(v)) for v in [*T[:3, 3], *q])


def look_at(eye, target):
    """Optical-frame pose at eye looking at target with zero roll (canopy's look_at)."""
    eye, target = np.asarray(eye, float), np.asarray(target, float)
    z = (target - eye) / np.linalg.norm(target - eye)
    x = np.cross(z, [0.0, 0.0, 1.0])
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x, np.cross(z, x), z, eye
    return T
