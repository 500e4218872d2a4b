"""Worlds from Python: generation, ground truth (against `canopy world`), rendering (against
the ground truth and the robot's kinematics), and the lifetime of frame arrays."""

import csv
import gc
import json

import numpy as np
import pytest

import canopy
from conftest import look_at


def test_generation_is_deterministic_and_seeded(world):
    again = canopy.World("worlds/small.yaml")
    assert np.array_equal(again.fruits["center"], world.fruits["center"])
    assert again.triangles == world.triangles
    other = canopy.World("worlds/small.yaml", seed=world.seed + 1)
    assert other.seed == world.seed + 1
    assert not np.array_equal(other.fruits["center"], world.fruits["center"])


def test_ground_truth_equals_the_cli_world(world, cli, tmp_path):
    cli("world", "--world", "worlds/small.yaml", "--out", tmp_path / "w")
    fruits = json.load(open(tmp_path / "w" / "fruits.json"))["fruits"]
    assert [f["instance_id"] for f in fruits] == list(world.fruits["instance_id"])
    assert np.array_equal(np.array([f["center"] for f in fruits]), world.fruits["center"])
    assert np.array_equal(np.array([f["bbox_min"] for f in fruits]), world.fruits["bbox_min"])
    assert [f["target"] for f in fruits] == list(world.fruits["target"])
    rows = list(csv.reader(open(tmp_path / "w" / "fruit_points.csv")))[1:]
    points = world.fruit_points()
    assert len(rows) == len(points["points"]) == world.fruits["surface_points"].sum()
    assert np.array_equal(np.array([[float(v) for v in r[1:]] for r in rows]), points["points"])
    summary = json.load(open(tmp_path / "w" / "world.json"))
    assert summary["plants"] == len(world.plants) and summary["plant_triangles"] == world.triangles
    assert sum(p["fruits"] for p in world.plants) == len(world.fruits["instance_id"])


def test_rendered_fruit_pixels_lie_on_their_fruit(world):
    """Instance pixels unprojected with their depth land inside that fruit's true box."""
    i = int(np.argmax(world.fruits["target"]))
    center = world.fruits["center"][i]
    eye = center + np.array([0.0, -0.3 * np.sign(center[1]), 0.05])  # from the aisle side
    frame = world.render(look_at(eye, center))
    K, T = frame.intrinsics, frame.pose
    assert frame.rgb.shape == (K.height_px, K.width_px, 3) and frame.rgb.dtype == np.uint8
    assert frame.depth.dtype == np.float32 and frame.labels.dtype == np.uint8 and frame.instances.dtype == np.int32
    fruit_id = world.fruits["instance_id"][i]
    rows, cols = np.nonzero((frame.instances == fruit_id) & (frame.depth > 0))
    assert len(rows) > 500, "the fruit fills part of the image"
    z = frame.depth[rows, cols].astype(float)
    p_cam = np.stack([(cols + 0.5 - K.cx_px) / K.fx_px * z, (rows + 0.5 - K.cy_px) / K.fy_px * z, z], axis=1)
    p_world = p_cam @ T[:3, :3].T + T[:3, 3]
    tol = 0.004
    assert np.all(p_world >= world.fruits["bbox_min"][i] - tol) and np.all(p_world <= world.fruits["bbox_max"][i] + tol)
    assert np.all(frame.labels[rows, cols] == world.classes.index("fruit"))
    assert np.all(frame.instances[frame.labels == 0] == -1)


def test_frame_arrays_outlive_their_frame_and_are_read_only(world):
    frame = world.render(look_at([0.0, -0.2, 0.7], [0.0, 0.75, 0.6]))
    depth, rgb = frame.depth, frame.rgb
    depth_copy, rgb_copy = depth.copy(), rgb.copy()
    del frame
    gc.collect()
    assert np.array_equal(depth, depth_copy) and np.array_equal(rgb, rgb_copy)
    assert not depth.flags.writeable
    with pytest.raises(ValueError):
        depth[0, 0] = 1.0


def test_wrist_camera_follows_the_robot_kinematics(world):
    robot = canopy.Robot()
    base = world.robot_start
    frame = world.render_robot(base)
    assert np.allclose(frame.pose, robot.camera_pose(base, robot.home), atol=1e-6)
    q = robot.home + np.array([0.2, 0.0, 0.0, 0.0, 0.1, 0.0])
    assert np.allclose(world.render_robot(base, q).pose, robot.camera_pose(base, q), atol=1e-6)


def test_view_presets(world):
    ring = world.views("ring")
    assert ring.shape == (8 * 2 * len(world.plants), 4, 4)
    assert np.allclose(np.einsum("nij,nkj->nik", ring[:, :3, :3], ring[:, :3, :3]), np.eye(3), atol=1e-9)
