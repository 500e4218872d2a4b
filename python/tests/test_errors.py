"""Bad input raises ValueError naming the value (never a crash); errors inside a Python planner
reach the caller as they were raised; a planner's request does not outlive its call."""

import numpy as np
import pytest

import canopy


def raises(fragment, fn, *args, **kwargs):
    with pytest.raises(ValueError) as e:
        fn(*args, **kwargs)
    assert fragment in str(e.value), str(e.value)
    return str(e.value)


def test_worlds_and_settings(tmp_path):
    raises("worlds/nope.yaml", canopy.World, "worlds/nope.yaml")
    raises("-1", canopy.World, "worlds/small.yaml", seed=-1)
    raises("'3'", canopy.World, "worlds/small.yaml", seed="3")
    bad = tmp_path / "bad.yaml"
    bad.write_text("rows: {rows: 7}\n")
    raises("rows", canopy.World, str(bad))
    s = canopy.Settings()
    message = raises("views_per_stop", s.set, "mission.loop.views_per_stop", -1)
    assert "-1" in message
    raises("no.such.key", s.set, "no.such.key", 1)
    raises("no.such.key", s.get, "no.such.key")
    raises("greedy", s.set, "method.name", "greedy")
    raises("/nowhere.yaml", canopy.Settings, "/nowhere.yaml")
    assert s.get("mission.loop.views_per_stop") == 12  # unchanged by the failed sets
    raises("settings", canopy.Map, settings=42)


def test_maps_and_frames(world, tmp_path):
    raises("classes", canopy.Map, classes=["leaf", "fruit"])
    raises("target", canopy.Map, target="pepper")
    raises("missing.csm", canopy.Map.load, str(tmp_path / "missing.csm"))
    (tmp_path / "junk.csm").write_bytes(b"not a map")
    raises("junk.csm", canopy.Map.load, str(tmp_path / "junk.csm"))
    m = canopy.Map(classes=world)
    raises("points", m.occupancy, np.zeros((4, 2)))
    raises("points", m.occupancy, [[0.0, np.nan, 1.0]])
    raises("points", m.known, "abc")
    raises("which", m.voxels, "some")
    raises("region", m.voxels, "all", region=[[1, 1, 1], [0, 0, 0]])
    pose = np.eye(4)
    raises("depth", canopy.Frame, np.zeros((10, 10)), pose)  # not the intrinsics' 400 x 400
    raises("pose", canopy.Frame, np.zeros((400, 400)), np.ones((4, 4)))
    raises("width_px", canopy.Intrinsics, width_px=0)
    raises("labels", canopy.Frame, np.zeros((400, 400)), pose, labels=np.full((400, 400), 258))  # would wrap to 2
    raises("rgb", canopy.Frame, np.zeros((400, 400)), pose, rgb=np.full((400, 400, 3), 0.5))
    raises("max_dt", canopy.read_frames, str(tmp_path), max_dt=0.0)
    raises("path", canopy.Map.load, 3)
    frame = canopy.Frame(np.full((400, 400), 0.5), pose, labels=np.zeros((400, 400)))
    raises("rgb", m.insert, frame)  # the default extractor segments colour
    raises("labels", m.insert_cloud, np.zeros((3, 3)), [1, 2], [0, 0, 0])
    raises("pose", world.render, np.diag([1.0, 1.0, -1.0, 1.0]))  # a reflection
    raises("joints", world.render_robot, world.robot_start, [9.0] * 6)
    with pytest.raises(ValueError):
        canopy.read_frames(str(tmp_path / "none"))


def test_planning(world):
    m = canopy.Map(classes=world)
    raises("entropy", canopy.gains, m, np.eye(4), [0, 0, 1], gain="entropy")
    raises("rays", canopy.gains, m, np.eye(4), [0, 0, 1], rays="all")
    raises("targets", canopy.gains, m, np.stack([np.eye(4)] * 2), [0, 0, 1])
    raises("base", canopy.next_views, m, [0.0, 0.0])
    raises("joints", canopy.next_views, m, [0.0, 0.0, 0.0], joints=[0.0] * 5)
    raises("greedy", canopy.next_views, m, [0.0, 0.0, 0.0], method="greedy")
    raises("planner=", canopy.next_views, m, [0.0, 0.0, 0.0], method="python")
    raises("centroid", canopy.sample_candidates, [0.0, 1.0])
    raises("seed", canopy.Robot().ik, [0, 0, 0], np.eye(4), seed=[0.0])


def test_missions(world, tmp_path):
    raises("greedy", canopy.run_mission, world, method="greedy")
    raises("planner", canopy.run_mission, world, planner=42)
    raises("two planners", canopy.run_mission, world, method="ours", planner=lambda r: [])
    raises("video_size", canopy.run_mission, world, video=str(tmp_path / "v.mp4"), video_size=(65, 64))
    raises("progress", canopy.run_mission, world, progress="loud")
    raises("seed", canopy.run_mission, world, seed=-2)
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("the user's")
    raises("mine", canopy.run_mission, world, out=str(tmp_path / "mine"))
    assert (tmp_path / "mine" / "notes.txt").read_text() == "the user's"


def settings0():
    """A short mission: two initial views, then the planner once."""
    return canopy.Settings().update({"mission.loop.views_per_stop": 1, "mission.loop.max_rounds": 2,
                                     "mission.scan.azimuths_deg": [0], "mission.scan.heights_m": [0.7]})


@pytest.mark.parametrize("answer, fragment", [
    (None, "returned None"),
    ("views", "returned 'views'"),
    ([np.eye(3)], "view 0"),
    ([{"pose": np.eye(4), "colour": 1}], "colour"),
    ([{"target": [0, 0, 0]}], "no 'pose'"),
    ([{"pose": np.eye(4), "joints": [0.0] * 6, "gain": "high"}], "gain"),
    ([{"pose": np.eye(4), "source": "my,source"}], "my,source"),
    ({"views": [], "order": "random"}, "random"),
    ([{"pose": np.eye(4), "cluster": 2**62}], "cluster: 4611686018427387904 is not an integer in"),
])
def test_bad_planner_answers(world, answer, fragment):
    raises(fragment, canopy.run_mission, world, settings0(), planner=lambda request: answer)


def test_errors_inside_the_planner_propagate(world, tmp_path):
    def broken(request):
        return 1 / 0

    with pytest.raises(ZeroDivisionError):
        canopy.run_mission(world, settings0(), planner=broken, out=str(tmp_path / "run"))
    assert not (tmp_path / "run").exists() and not (tmp_path / "run.partial").exists()


def test_requests_end_with_their_call(world):
    kept = []

    def keep(request):
        kept.append((request, request.map))
        return []

    canopy.run_mission(world, settings0(), planner=keep)
    request, lent = kept[0]
    raises("has returned", lambda: request.camera)
    raises("has returned", request.reach, np.eye(4))
    raises("lent", lent.counts)
    raises("read-only", lent.insert_cloud, np.zeros((1, 3)), [1], [0, 0, 1])
