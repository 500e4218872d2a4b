"""ROS 1 bags in and out with Debian's python3-rosbag (canopy.bag; docs/real_robot.md#ros-bags):
a mission written as a bag and mapped back gives the mission's map.csm byte for byte; the reader
takes 16UC1 and 32FC1 depth, compressed RGB, /tf_static and interpolated /tf; a missing
transform, a wrong encoding, out-of-order stamps and a missing topic are one clear error (exit
code 2 from `python3 -m canopy`). map-bag streams (memory does not grow with the recording),
checks declared image sizes before decoding, takes a recording's labels without simulated
noise and only the depth images' own frame; a bag is never written over a file canopy did not
write nor into a canopy output folder, and a full disk is one line naming the file."""

import io
import json
import os
import resource
import shutil
import struct
import subprocess
import sys
import zlib

import numpy as np
import pytest
import yaml

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


def run_cli(*args, **kwargs):
    return subprocess.run([sys.executable, "-m", "canopy", *map(str, args)], capture_output=True, text=True,
                          cwd=SOURCE, **kwargs)


def cli_fails(*args, **kwargs):
    """Runs `python3 -m canopy ARGS`, which must fail with exit code 2 and one error line, its last
    line (progress lines may come before it); returns that line."""
    p = run_cli(*args, **kwargs)
    assert p.returncode == 2, p.stdout + p.stderr
    lines = p.stderr.strip().splitlines()
    assert [line for line in lines if line.startswith("canopy: error")] == lines[-1:], p.stderr
    return lines[-1]


def hidden_leftovers(folder):
    return sorted(n for n in os.listdir(folder) if n.startswith(".") or n.endswith((".partial", ".lock")))


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
        for key in ("rgb", "depth", "labels", "labels_color", "camera_info", "map", "views", "view_record"):
            assert topics[cbag.TOPICS[key]].message_count == n, key
        records = [json.loads(m.data) for _, m, _ in b.read_messages(topics=[cbag.TOPICS["view_record"]])]
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
    # The frustums in the report's phase colours, and each view's record by the schema's names.
    colours = {p["name"]: p["colour"] for p in canopy.vocabulary()["view_phases"]}
    for m in last_views.markers:
        assert "#%02x%02x%02x" % tuple(round(255 * c) for c in (m.color.r, m.color.g, m.color.b)) == colours[m.ns]
    known = [f["name"] for f in canopy.view_fields() if f["known_when_taken"]]
    assert list(cbag.VIEW_RECORD_FIELDS) == known
    assert [list(r) for r in records] == [known] * n
    ok = result.views["success"]
    assert [r["attempt"] for r in records] == list(result.views["attempt"][ok])
    assert np.allclose([r["goal_pose"] for r in records], result.views["goal_pose"][ok])
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
        canopy.read_bag(tmp_path / "r.bag", frame="nowhere", override_frame=True, **TOPICS)


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


def test_labels_and_stamps_follow_the_cpp_rules(tmp_path):
    """The bag reader decodes colour labels by datasets::ClassColorTable::decode and pairs stamps
    by datasets::nearest_timestamp (bound as canopy.decode_class_colors and canopy.nearest_stamps):
    a stray colour is the C++ message, and the pairing equals a brute-force reference."""
    colors = canopy.class_colors(["background", "leaf", "fruit"])
    ids = np.zeros((H, W), np.uint8)
    ids[2:4, 1:6] = 2
    rgb = colors[ids]
    assert np.array_equal(canopy.decode_class_colors(rgb, colors), ids)
    rgb[5, 3] = (1, 2, 3)
    with pytest.raises(ValueError, match=r"^x: colour \(1, 2, 3\) at pixel \(3, 5\) is not in the class-colour table$"):
        canopy.decode_class_colors(rgb, colors, "x")
    with rosbag.Bag(str(tmp_path / "s.bag"), "w") as b:
        b.write("/tf_static", tf_msg("world", "cam", 0.0, (0.0, 0.0, 1.0)), stamp(0.5))
        b.write("/cam/info", info(1.0), stamp(1.0))
        b.write("/cam/depth", image(1.0, np.full((H, W), 750, np.uint16), "16UC1"), stamp(1.0))
        b.write("/cam/labels", image(1.0, rgb, "rgb8"), stamp(1.0))
    with pytest.raises(canopy.BagError, match=r"/cam/labels.*: colour \(1, 2, 3\) at pixel \(3, 5\) is not in the "
                                              r"class-colour table"):
        canopy.read_bag(tmp_path / "s.bag", rgb=None, depth="/cam/depth", camera_info="/cam/info", labels="/cam/labels")
    # Nearest within the tolerance, the earlier of two equally near, -1 beyond it.
    rng = np.random.default_rng(3)
    sorted_t = np.unique(np.round(rng.uniform(0, 10, 40), 2))  # a topic's stamps increase (the reader checks)
    queries = np.round(rng.uniform(-1, 11, 200), 3)
    for max_dt in (0.0, 0.02, 0.5, np.inf):
        got = canopy.nearest_stamps(sorted_t, queries, max_dt)
        for q, j in zip(queries, got):
            d = np.abs(sorted_t - q)
            want = int(np.argmin(d)) if d.min() <= max_dt else -1  # argmin: the first (earlier) of ties
            assert j == want, (q, max_dt)
    with pytest.raises(ValueError, match="must not decrease"):
        canopy.nearest_stamps([1.0, 0.5], [0.7])


# --- what canopy writes, and where -------------------------------------------------------------

def test_a_bag_never_replaces_what_canopy_did_not_write(mission_bag, world, tmp_path):
    """An existing file at the bag's name is replaced only when canopy wrote it (its marker); a
    bag is never written into a canopy output folder, which that command's next run replaces
    whole. Refusals come before the replay, leave the file as it was and nothing beside it."""
    tmp, settings, result = mission_bag
    lab = tmp_path / "lab.bag"
    write_bag(lab)  # a lab's recording
    before = lab.read_bytes()
    assert "lab.bag: exists and is not a bag canopy wrote" in cli_fails("export-bag", tmp / "run", lab)
    assert lab.read_bytes() == before
    # A recording of a canopy bag played back carries the marker topic, not canopy's connection header.
    rerecorded = tmp_path / "rerecorded.bag"
    with rosbag.Bag(str(tmp / "run.bag")) as src, rosbag.Bag(str(rerecorded), "w") as dst:
        for topic, msg, t in src.read_messages(topics=[cbag.WRITER_TOPIC, "/tf"]):
            dst.write(topic, msg, t)
    assert cbag.is_canopy_bag(tmp / "run.bag") and not cbag.is_canopy_bag(rerecorded)
    assert not cbag.is_canopy_bag(lab) and not cbag.is_canopy_bag(tmp / "run" / "summary.json")
    assert "exists and is not a bag canopy wrote" in cli_fails("export-bag", tmp / "run", rerecorded)
    # Inside the run folder (a canopy output): refused, nothing written there.
    line = cli_fails("export-bag", tmp / "run", tmp / "run" / "run.bag")
    assert "is inside" in line and str(tmp / "run") in line
    assert not (tmp / "run" / "run.bag").exists() and hidden_leftovers(tmp / "run") == [".canopy-output"]
    (tmp_path / "out").mkdir()
    with pytest.raises(canopy.BagError, match="is inside out"):
        canopy.record_bag(world, tmp_path / "out" / "x.bag", settings, out=tmp_path / "out")
    assert os.listdir(tmp_path / "out") == []
    # A bag canopy wrote is replaced by the new one.
    ours = tmp_path / "ours.bag"
    shutil.copy(tmp / "run.bag", ours)
    p = run_cli("export-bag", tmp / "run", ours)
    assert p.returncode == 0, p.stderr
    assert cbag.is_canopy_bag(ours)
    with rosbag.Bag(str(ours)) as b:
        assert b.get_type_and_topic_info().topics[cbag.TOPICS["depth"]].message_count == result.successful_views
    assert hidden_leftovers(tmp_path) == []


@pytest.fixture
def tiny_disk(tmp_path):
    """A 1 MB tmpfs (mounting needs root; skipped without it)."""
    d = tmp_path / "tiny"
    d.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(d)], capture_output=True).returncode:
        pytest.skip("cannot mount a tmpfs here (needs root)")
    yield d
    subprocess.run(["umount", str(d)], check=True)


def test_export_bag_on_a_full_disk(mission_bag, tiny_disk):
    tmp = mission_bag[0]
    line = cli_fails("export-bag", tmp / "run", tiny_disk / "run.bag")
    assert f"{tiny_disk / 'run.bag'}: cannot write the bag: the disk is full" in line
    assert os.listdir(tiny_disk) == []


def test_export_bag_past_the_file_size_limit(mission_bag, tmp_path):
    """RLIMIT_FSIZE (ulimit -f): the write fails with EFBIG (canopy ignores SIGXFSZ) and says so."""
    tmp = mission_bag[0]

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (1 << 20, 1 << 20))

    line = cli_fails("export-bag", tmp / "run", tmp_path / "run.bag", preexec_fn=limit)
    assert f"{tmp_path / 'run.bag'}: cannot write the bag: the file size limit is reached" in line
    assert os.listdir(tmp_path) == []


# --- reading: streamed, checked before decoding ------------------------------------------------

def write_long_bag(path, n, width=640, height=480, stamp0=1.0, period=0.05):
    """n frames of a static camera 0.5 m before a wall, LZ4-compressed: 16UC1 depth, valid on a
    small patch only (mapping each frame stays cheap, reading and decoding it does not), rgb8."""
    d = np.zeros((height, width), np.uint16)
    d[height // 2 - 4:height // 2 + 4, width // 2 - 4:width // 2 + 4] = 500
    rgb = np.zeros((height, width, 3), np.uint8)
    rgb[:, :, 1] = 160
    rgb[::7, :, 0] = 90
    cam_info = CameraInfo()
    cam_info.header.frame_id, cam_info.width, cam_info.height = "cam", width, height
    cam_info.K = [width * 0.8, 0, width / 2 - 0.5, 0, width * 0.8, height / 2 - 0.5, 0, 0, 1]
    with rosbag.Bag(str(path), "w", compression="lz4") as b:
        b.write("/tf_static", tf_msg("world", "cam", 0.0, (0.0, 0.0, 1.0)), stamp(0.5))
        for k in range(n):
            t = stamp0 + k * period
            cam_info.header.stamp = stamp(t)
            b.write("/cam/info", cam_info, stamp(t))
            b.write("/cam/depth", image(t, d, "16UC1"), stamp(t))
            b.write("/cam/rgb", image(t, rgb, "rgb8"), stamp(t))


MAP_IN_CHILD = """
import resource, sys, canopy
r = canopy.map_bag(sys.argv[1], sys.argv[2], rgb="/cam/rgb", depth="/cam/depth", camera_info="/cam/info")
print(r["mapped"], resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024)
"""


def test_map_bag_memory_does_not_grow_with_the_recording(tmp_path):
    """Peak memory of mapping 20 and 80 frames of 640 x 480 in a child process: holding the
    recording costs 3.9 MB a frame (230 MB more for the longer one); streamed, the peak is the
    same within 40 MB."""
    peaks = {}
    for n in (20, 80):
        write_long_bag(tmp_path / f"{n}.bag", n)
        p = subprocess.run([sys.executable, "-c", MAP_IN_CHILD, tmp_path / f"{n}.bag", tmp_path / f"out{n}"],
                           capture_output=True, text=True, cwd=SOURCE)
        assert p.returncode == 0, p.stderr
        mapped, peaks[n] = map(int, p.stdout.split())
        assert mapped == n
    assert peaks[80] - peaks[20] < 40, peaks


def test_map_bag_says_what_it_reads(tmp_path, monkeypatch):
    """A line while the first pass reads (every PROGRESS_PERIOD_S), one before mapping naming the
    frames, the camera frame and the labels, then one per frame."""
    write_long_bag(tmp_path / "r.bag", 3, width=64, height=48)
    monkeypatch.setattr(cbag.read, "PROGRESS_PERIOD_S", 0.0)
    lines = []
    canopy.map_bag(tmp_path / "r.bag", tmp_path / "out", rgb="/cam/rgb", depth="/cam/depth", camera_info="/cam/info",
                   progress=lines.append)
    assert lines[0].startswith(f"reading {tmp_path / 'r.bag'}: 1 of 10 messages")
    mapping = next(i for i, line in enumerate(lines) if line.startswith("read "))
    assert "mapping 3 frames (0 skipped), camera frame 'cam'" in lines[mapping]
    assert [line.split(":")[0] for line in lines[mapping + 1:]] == [f"frame /cam/depth@{1 + 0.05 * k:.9f}"
                                                                     for k in range(3)]


def png_bytes(a, declared=None):
    """PNG of array a; with declared=(w, h), its header claims that size (CRC kept valid)."""
    from PIL import Image as PILImage
    buf = io.BytesIO()
    PILImage.fromarray(a).save(buf, format="PNG")
    data = bytearray(buf.getvalue())
    if declared is not None:  # IHDR: after the 8-byte signature, length and type; then width, height
        data[16:24] = struct.pack(">II", *declared)
        data[29:33] = struct.pack(">I", zlib.crc32(bytes(data[12:29])))
    return bytes(data)


def compressed_rgb_bag(path, data):
    with rosbag.Bag(str(path), "w") as b:
        b.write("/tf_static", tf_msg("world", "cam", 0.0, (0.0, 0.0, 1.0)), stamp(0.5))
        b.write("/cam/info", info(1.0), stamp(1.0))
        b.write("/cam/depth", image(1.0, np.full((H, W), 500, np.uint16), "16UC1"), stamp(1.0))
        c = CompressedImage(format="png", data=data)
        c.header.stamp, c.header.frame_id = stamp(1.0), "cam"
        b.write("/cam/rgb", c, stamp(1.0))


def test_image_sizes_are_checked_before_decoding(tmp_path):
    """A PNG declaring 4096 x 4096 (its data is 8 x 6's) is refused by its declared size, naming
    the topic and the stamp, before a pixel is decoded; a truncated PNG of the right size names
    them too."""
    rgb = np.zeros((H, W, 3), np.uint8)
    compressed_rgb_bag(tmp_path / "big.bag", png_bytes(rgb, declared=(4096, 4096)))
    line = cli_error(tmp_path, tmp_path / "big.bag")
    assert "/cam/rgb at 1.000000000 s: rgb image of 4096 x 4096 px, but camera_info says 8 x 6" in line
    noise = png_bytes(np.random.default_rng(1).integers(0, 255, (H, W, 3), dtype=np.uint8))
    compressed_rgb_bag(tmp_path / "cut.bag", noise[:len(noise) // 2])
    line = cli_fails("map-bag", tmp_path / "cut.bag", "--out", tmp_path / "out", "--rgb", "/cam/rgb", "--depth",
                     "/cam/depth", "--camera-info", "/cam/info")
    assert line == ("canopy: error: /cam/rgb at 1.000000000 s: a CompressedImage (png) that cannot be decoded: image "
                    "file is truncated")
    assert not (tmp_path / "out").exists() and hidden_leftovers(tmp_path) == []


# --- a recording's labels and frames -----------------------------------------------------------

def test_a_recordings_labels_are_taken_as_they_are(mission_bag, tmp_path):
    """No simulated mask noise unless --pgt asks: with a bundle whose p_gt is 0.7 (the
    simulator's), the true-label bag maps to the mission's map (p_gt 1) byte for byte, the
    progress says so, and run.yaml and settings.yaml record p_gt 1; --pgt 0.7 draws noise."""
    tmp, settings, _ = mission_bag
    noisy = settings.copy().set("mapping.extractor.p_gt", 0.7)
    noisy.save(tmp_path / "noisy.yaml")
    p = run_cli("map-bag", tmp / "run.bag", "--out", tmp_path / "a", "--config", tmp_path / "noisy.yaml")
    assert p.returncode == 0, p.stderr
    assert "no simulated mask noise (p_gt 1" in p.stderr
    assert (tmp_path / "a" / "map.csm").read_bytes() == (tmp / "run" / "map.csm").read_bytes()
    run = yaml.safe_load((tmp_path / "a" / "run.yaml").read_text())
    assert run["p_gt"] == 1.0 and run["frame"] == "camera_optical_frame"
    assert canopy.Settings(str(tmp_path / "a" / "settings.yaml")).get("mapping.extractor.p_gt") == 1.0
    p = run_cli("map-bag", tmp / "run.bag", "--out", tmp_path / "b", "--config", tmp_path / "noisy.yaml", "--pgt", 0.7)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "b" / "map.csm").read_bytes() != (tmp / "run" / "map.csm").read_bytes()


def test_the_frame_is_the_depth_images_own(tmp_path):
    """--frame naming another frame than the depth images' frame_id is refused, naming both;
    --override-frame takes it with a warning; run.yaml records the frame used."""
    write_bag(tmp_path / "r.bag")
    line = cli_error(tmp_path, tmp_path / "r.bag", "--frame", "base")
    assert "frame 'base' is not the depth images' frame 'cam'" in line
    topics = ["--rgb", "/cam/rgb", "--depth", "/cam/depth", "--camera-info", "/cam/info"]
    p = run_cli("map-bag", tmp_path / "r.bag", "--out", tmp_path / "o", *topics, "--frame", "base", "--override-frame")
    assert p.returncode == 0 and "warning: /cam/depth: poses of frame 'base'" in p.stderr, p.stderr
    assert yaml.safe_load((tmp_path / "o" / "run.yaml").read_text())["frame"] == "base"
    p = run_cli("map-bag", tmp_path / "r.bag", "--out", tmp_path / "d", *topics)
    assert p.returncode == 0, p.stderr
    assert yaml.safe_load((tmp_path / "d" / "run.yaml").read_text())["frame"] == "cam"


@pytest.mark.parametrize("command", ["map-bag", "export-bag"])
def test_help_shows_every_default(command):
    p = run_cli(command, "--help")
    assert p.returncode == 0, p.stderr
    entries, current = [], None  # each argument's help: from its name to the next argument
    for line in p.stdout.splitlines():
        if line.startswith("  ") and not line.startswith("   ") or line.startswith("  -"):
            current = [line]
            entries.append(current)
        elif current is not None and line.startswith("    "):
            current.append(line)
        else:
            current = None
    texts = [" ".join(" ".join(e).split()) for e in entries if not e[0].strip().startswith("-h")]
    assert texts and all("(default:" in t or "(required)" in t for t in texts), texts


def test_canopy_map_frames_help_shows_its_defaults():
    p = subprocess.run([os.environ["CANOPY_CLI"], "map", "--help"], capture_output=True, text=True, cwd=SOURCE)
    text = " ".join(p.stdout.split())
    assert "with --frames 1 (recorded labels are taken as they are)" in text
    assert "0.02" in text and "DIR/camera.yaml" in text
