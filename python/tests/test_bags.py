"""ROS 1 bags in and out with Debian's python3-rosbag (canopy.bag; docs/real_robot.md#ros-bags):
a mission written as a bag and mapped back gives the mission's map.csm byte for byte; the reader
takes 16UC1 and 32FC1 depth, compressed RGB, /tf_static and interpolated /tf; a missing
transform, a wrong encoding, out-of-order stamps and a missing topic are one clear error (exit
code 2 from `python3 -m canopy`)."""

import io
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import canopy
from canopy import bag as cbag

import genpy  # Debian's ROS 1 packages (tools/deps.sh): the tests use the real library
import rosbag
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import CameraInfo, CompressedImage, Image
from tf2_msgs.msg import TFMessage

from conftest import SOURCE


def settings_for(source):
    s = canopy.Settings()
    s.set("mapping.extractor.source", source)
    s.set("mapping.extractor.p_gt", 1.0)
    s.set("mission.loop.views_per_stop", 2)
    s.set("mission.scan.azimuths_deg", [0])  # an initial scan of 4 views: the tests stay short
    return s


def run_cli(*args):
    env = dict(os.environ)
    return subprocess.run([sys.executable, "-m", "canopy", *map(str, args)], capture_output=True, text=True,
                          cwd=SOURCE, env=env)


@pytest.fixture(scope="module")
def mission_bag(world, tmp_path_factory):
    """The small world's mission (true labels, no mask noise, 4 initial views and 2 more) with its
    bag."""
    tmp = tmp_path_factory.mktemp("mission")
    settings = settings_for("truth")
    result = canopy.record_bag(world, tmp / "run.bag", settings, seed=3, out=tmp / "run")
    return tmp, settings, result


def test_round_trip_gives_the_missions_map(mission_bag):
    tmp, settings, result = mission_bag
    assert result.successful_views >= 5, result.summary["end_reason"]
    r = canopy.map_bag(tmp / "run.bag", tmp / "mapped", settings)
    assert r["mapped"] == result.successful_views and r["skipped"] == 0
    assert (tmp / "mapped" / "map.csm").read_bytes() == (tmp / "run" / "map.csm").read_bytes()
    for name in ("map.ply", "map.bt", "frames.json", "run.yaml", "settings.yaml"):
        assert (tmp / "mapped" / name).is_file()
    # The command line gives the same folder.
    p = run_cli("map-bag", tmp / "run.bag", "--out", tmp / "mapped_cli", "--config", tmp / "run" / "settings.yaml")
    assert p.returncode == 0, p.stderr
    assert (tmp / "mapped_cli" / "map.csm").read_bytes() == (tmp / "run" / "map.csm").read_bytes()


def test_bag_holds_images_tf_map_views_and_fruits(mission_bag, world):
    tmp, _, result = mission_bag
    with rosbag.Bag(str(tmp / "run.bag")) as b:
        topics = b.get_type_and_topic_info().topics
        n = result.successful_views
        for key in ("rgb", "depth", "labels", "labels_color", "camera_info", "map", "views"):
            assert topics[cbag.TOPICS[key]].message_count == n, key
        assert topics[cbag.TOPICS["fruits"]].message_count == 1
        assert topics["/tf"].message_count > n  # the views' and the state ticks'
        frames = set()
        last_cloud = last_views = None
        for topic, msg, _ in b.read_messages(topics=["/tf", cbag.TOPICS["map"], cbag.TOPICS["views"]]):
            if topic == "/tf":
                frames |= {t.child_frame_id for t in msg.transforms}
            elif topic == cbag.TOPICS["map"]:
                last_cloud = msg
            else:
                last_views = msg
    assert {"base_link", "shoulder_link", "wrist_3_link", "tool0", "camera_optical_frame"} <= frames
    assert last_cloud.width == len(result.map.voxels("occupied")["center"])
    assert len(last_views.markers) == n
    assert {m.ns for m in last_views.markers} <= {"initial", "nbv", "predefined"}
    # Each frame's pose from /tf is the pose the mission mapped it with.
    frames = canopy.read_bag(tmp / "run.bag", labels=cbag.TOPICS["labels"], min_range=world.camera.min_range_m,
                             max_range=world.camera.max_range_m)["frames"]
    reached = result.views["reached_pose"][result.views["success"]]
    assert np.allclose([f.pose for f in frames], reached, atol=1e-12)


def test_export_bag_replays_the_run_folder(mission_bag):
    tmp, _, result = mission_bag
    p = run_cli("export-bag", tmp / "run", tmp / "exported.bag")
    assert p.returncode == 0, p.stderr
    with rosbag.Bag(str(tmp / "exported.bag")) as b:
        assert b.get_type_and_topic_info().topics[cbag.TOPICS["depth"]].message_count == result.successful_views
    # A views.csv the replay does not give is refused, and no bag is written.
    bad = tmp / "edited"
    bad.mkdir()
    for name in ("summary.json", "settings.yaml"):
        (bad / name).write_bytes((tmp / "run" / name).read_bytes())
    (bad / "views.csv").write_text((tmp / "run" / "views.csv").read_text().replace(",nbv,", ",xxx,", 1))
    with pytest.raises(canopy.BagError, match="replaying the run gave other views than its views.csv"):
        canopy.export_bag(bad, tmp / "edited.bag")
    assert not (tmp / "edited.bag").exists() and not list(tmp.glob(".edited.bag*"))


# --- hand-made bags -----------------------------------------------------------------------------

W, H = 8, 6


def stamp(t):
    return genpy.Time.from_sec(t)


def tf_msg(parent, child, t, xyz, q=(0.0, 0.0, 0.0, 1.0)):
    m = TransformStamped()
    m.header.stamp, m.header.frame_id, m.child_frame_id = stamp(t), parent, child
    m.transform.translation.x, m.transform.translation.y, m.transform.translation.z = xyz
    m.transform.rotation.x, m.transform.rotation.y, m.transform.rotation.z, m.transform.rotation.w = q
    return TFMessage(transforms=[m])


def image(t, a, encoding, frame="cam"):
    a = np.ascontiguousarray(a)
    m = Image()
    m.header.stamp, m.header.frame_id = stamp(t), frame
    m.height, m.width, m.encoding, m.step, m.data = a.shape[0], a.shape[1], encoding, a.strides[0], a.tobytes()
    return m


def info(t):
    m = CameraInfo()
    m.header.stamp, m.header.frame_id, m.width, m.height = stamp(t), "cam", W, H
    m.K = [10.0, 0, 3.5, 0, 10.0, 2.5, 0, 0, 1]
    return m


def write_bag(path, depth_stamps=(1.0, 1.5), depth_encoding="16UC1", tf_child="base", compressed_rgb=False):
    """A small recording: world -> base (/tf at t = 1 and 2), base -> cam (/tf_static), depth
    images 0.5 m, RGB images 1 ms later."""
    rgb = np.zeros((H, W, 3), np.uint8)
    rgb[:, :, 0] = 200
    with rosbag.Bag(str(path), "w") as b:
        b.write("/tf_static", tf_msg("base", "cam", 0.0, (0.0, 0.0, 1.0)), stamp(0.5))
        b.write("/tf", tf_msg("world", tf_child, 1.0, (0.0, 0.0, 0.0)), stamp(1.0))
        b.write("/tf", tf_msg("world", tf_child, 2.0, (1.0, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0)), stamp(2.0))
        for k, t in enumerate(depth_stamps):
            received = stamp(3.0 + k)  # the bag's own times keep the order of writing
            b.write("/cam/info", info(t), received)
            d = np.full((H, W), 500, np.uint16) if depth_encoding in ("16UC1", "mono16") else \
                np.full((H, W), 0.5, np.float32) if depth_encoding == "32FC1" else np.zeros((H, W, 3), np.uint8)
            b.write("/cam/depth", image(t, d, depth_encoding), received)
            if compressed_rgb:
                from PIL import Image as PILImage
                buf = io.BytesIO()
                PILImage.fromarray(rgb).save(buf, format="PNG")
                c = CompressedImage(format="png", data=buf.getvalue())
                c.header.stamp, c.header.frame_id = stamp(t + 0.001), "cam"
                b.write("/cam/rgb", c, received)
            else:
                b.write("/cam/rgb", image(t + 0.001, rgb, "rgb8"), received)
    return rgb


TOPICS = dict(rgb="/cam/rgb", depth="/cam/depth", camera_info="/cam/info")


@pytest.mark.parametrize("encoding", ["16UC1", "32FC1"])
def test_reader_pairs_images_and_interpolates_tf(tmp_path, encoding):
    rgb = write_bag(tmp_path / "r.bag", depth_encoding=encoding, compressed_rgb=encoding == "32FC1")
    r = canopy.read_bag(tmp_path / "r.bag", **TOPICS)
    assert len(r["frames"]) == 2 and r["skipped"] == [] and r["stamps"] == [1.0, 1.5]
    f0, f1 = r["frames"]
    assert np.allclose(f0.depth, 0.5) and np.array_equal(f0.rgb, rgb)
    assert f0.intrinsics.cx_px == 4.0 and f0.intrinsics.cy_px == 3.0  # ROS's pixel centres at 0, canopy's at 0.5
    assert np.allclose(f0.pose[:3, 3], [0, 0, 1]) and np.allclose(f0.pose[:3, :3], np.eye(3))
    # Half-way between the samples (yaw 0 and 180 degrees): x 0.5, yaw 90 degrees (slerp), then the
    # static camera offset.
    assert np.allclose(f1.pose[:3, 3], [0.5, 0, 1]) and np.allclose(f1.pose[:3, :2], [[0, -1], [1, 0], [0, 0]])
    m = canopy.Map(settings_for("color"))
    assert m.insert(f0)["points"] > 0


def test_frames_outside_the_tf_samples_are_skipped(tmp_path):
    write_bag(tmp_path / "r.bag", depth_stamps=(1.0, 3.0))
    r = canopy.read_bag(tmp_path / "r.bag", **TOPICS)
    assert len(r["frames"]) == 1 and "after the last sample" in r["skipped"][0]["reason"]


def cli_error(tmp_path, bag, *extra):
    p = run_cli("map-bag", bag, "--out", tmp_path / "out", "--rgb", "/cam/rgb", "--depth", "/cam/depth",
                "--camera-info", "/cam/info", *extra)
    assert p.returncode == 2, p.stdout + p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert not (tmp_path / "out").exists()
    return lines[0]


def test_missing_transform_is_one_error(tmp_path):
    write_bag(tmp_path / "r.bag", tf_child="odom")  # world -> odom and base -> cam: no odom -> base
    with pytest.raises(canopy.BagError, match="separate trees"):
        canopy.read_bag(tmp_path / "r.bag", **TOPICS)
    assert "a transform between the trees is missing" in cli_error(tmp_path, tmp_path / "r.bag")
    with pytest.raises(canopy.BagError, match="frame 'nowhere' is not in the bag's /tf or /tf_static"):
        canopy.read_bag(tmp_path / "r.bag", frame="nowhere", **TOPICS)


def test_wrong_encoding_is_one_error(tmp_path):
    write_bag(tmp_path / "r.bag", depth_encoding="rgb8")
    line = cli_error(tmp_path, tmp_path / "r.bag")
    assert "/cam/depth: depth encoding 'rgb8' is not supported" in line


def test_out_of_order_stamps_are_one_error(tmp_path):
    write_bag(tmp_path / "r.bag", depth_stamps=(1.5, 1.0))
    line = cli_error(tmp_path, tmp_path / "r.bag")
    assert "/cam/depth: header stamps out of order" in line


def test_missing_topic_and_bad_files_are_errors(tmp_path):
    write_bag(tmp_path / "r.bag")
    with pytest.raises(canopy.BagError, match="topic /nothing .depth. is not in the bag .its topics: /cam/depth"):
        canopy.read_bag(tmp_path / "r.bag", **{**TOPICS, "depth": "/nothing"})
    with pytest.raises(canopy.BagError, match="topic /cam/info .rgb. is sensor_msgs/CameraInfo, not"):
        canopy.read_bag(tmp_path / "r.bag", **{**TOPICS, "rgb": "/cam/info", "camera_info": "/cam/info"})
    (tmp_path / "junk.bag").write_text("not a bag")
    with pytest.raises(canopy.BagError, match="not a readable ROS 1 bag"):
        canopy.read_bag(tmp_path / "junk.bag")
    with pytest.raises(canopy.BagError, match="no such file"):
        canopy.read_bag(tmp_path / "absent.bag")


def test_colour_round_trip_and_the_hooks_change_nothing(world, tmp_path):
    """Colour segmentation of the bag's RGB gives the map too; writing the bag (on_view, on_state)
    leaves the mission's views as they are without it."""
    settings = settings_for("color")
    result = canopy.record_bag(world, tmp_path / "c.bag", settings, seed=5, out=tmp_path / "run")
    assert canopy.run_mission(world, settings, seed=5).views_csv == result.views_csv
    canopy.map_bag(tmp_path / "c.bag", tmp_path / "mapped", settings)
    assert (tmp_path / "mapped" / "map.csm").read_bytes() == (tmp_path / "run" / "map.csm").read_bytes()


def test_ctrl_c_publishes_the_frames_mapped_so_far(tmp_path):
    """A KeyboardInterrupt in map_frames' progress (as Ctrl-C raises it) stops before the next
    frame: the folder holds the first frame's map, marked incomplete."""
    write_bag(tmp_path / "r.bag")
    frames = canopy.read_bag(tmp_path / "r.bag", **TOPICS)["frames"]

    def progress(line):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt, match="interrupted after 1 frames"):
        canopy.map_frames(frames, tmp_path / "out", settings_for("color"), progress=progress)

    record = json.loads((tmp_path / "out" / "frames.json").read_text())
    assert record["complete"] is False and record["frames_mapped"] == 1


def test_compressed_depth_and_colour_labels(tmp_path):
    """compressedDepth PNG (16UC1 millimetres after the transport's 12-byte header) and label
    images in the classes' colours."""
    from PIL import Image as PILImage

    colors = canopy.class_colors(["background", "leaf", "fruit"])
    ids = np.zeros((H, W), np.uint8)
    ids[1:3, 2:5] = 2
    ids[4:, :] = 1
    with rosbag.Bag(str(tmp_path / "c.bag"), "w") as b:
        b.write("/tf_static", tf_msg("world", "cam", 0.0, (0.0, 0.0, 1.0)), stamp(0.5))
        b.write("/cam/info", info(1.0), stamp(1.0))
        buf = io.BytesIO()
        PILImage.fromarray(np.full((H, W), 750, np.uint16)).save(buf, format="PNG")
        c = CompressedImage(format="16UC1; compressedDepth png", data=bytes(12) + buf.getvalue())
        c.header.stamp, c.header.frame_id = stamp(1.0), "cam"
        b.write("/cam/depth", c, stamp(1.0))
        b.write("/cam/labels", image(1.0, colors[ids], "rgb8"), stamp(1.0))
    r = canopy.read_bag(tmp_path / "c.bag", rgb=None, depth="/cam/depth", camera_info="/cam/info",
                        labels="/cam/labels")
    (f,) = r["frames"]
    assert np.allclose(f.depth, 0.75) and np.array_equal(f.labels, ids)
