"""Missions from Python: a built-in method gives `canopy mission`'s views.csv byte for byte; a
Python planner runs in the closed loop, gets what canopy's planners get, and is deterministic
for a seed; the example runs; the GIL is released while the mission runs."""

import importlib.util
import json
import signal
import subprocess
import sys
import threading

import numpy as np

import canopy
from conftest import SOURCE


def small_settings(views_per_stop=2, exploration="frontier"):
    return canopy.Settings().set("mission.loop.views_per_stop", views_per_stop).set("mission.loop.exploration",
                                                                                      exploration)


def load_example():
    spec = importlib.util.spec_from_file_location("coverage_greedy", SOURCE / "examples/python/coverage_greedy.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_builtin_method_equals_the_cli_mission(world, cli, tmp_path):
    cli("mission", "--world", "worlds/small.yaml", "--views-per-stop", 2, "--no-plots", "--out", tmp_path / "cli")
    result = canopy.run_mission(world, small_settings(), seed=1, out=str(tmp_path / "py"))
    assert result.views_csv == (tmp_path / "cli" / "views.csv").read_text()
    assert (tmp_path / "py" / "views.csv").read_text() == result.views_csv
    assert canopy.Map.load(str(tmp_path / "py" / "map.csm")) == result.map
    assert canopy.Map.load(str(tmp_path / "cli" / "map.csm")) == result.map
    assert json.load(open(tmp_path / "py" / "summary.json")) == result.summary
    assert (tmp_path / "py" / "report.html").is_file()
    # report=False is the command line's --no-report: the same run without report.html.
    canopy.run_mission(world, small_settings(), seed=1, out=str(tmp_path / "bare"), report=False)
    assert (tmp_path / "bare" / "views.csv").read_text() == result.views_csv
    assert not (tmp_path / "bare" / "report.html").exists()
    assert result.summary["method"]["name"] == "ours" and result.complete
    views = result.views
    ok = views["success"]
    curve = result.sc_curve()
    assert np.array_equal(curve["coverage"], views["coverage"][ok])
    assert list(curve["views"]) == list(range(1, int(ok.sum()) + 1))
    assert np.all(np.isnan(views["reached_pose"][~ok])) and not np.any(np.isnan(views["reached_pose"][ok]))
    assert result.stops[0]["nbv_successful"] == int(np.sum(ok & (views["phase"] == "nbv")))
    # Every column of views.csv, by name, with its values; then the fields kept out of it
    # (canopy.view_fields(): the poses, the target, the message, ...).
    header = result.views_csv.splitlines()[0].split(",")
    assert list(views) == [f["name"] for f in canopy.view_fields()]
    assert set(views) - set(header) == {f["name"] for f in canopy.view_fields() if not f["in_views_csv"]}
    rows = [line.split(",") for line in result.views_csv.splitlines()[1:]]
    for i, name in enumerate(header):
        assert len(views[name]) == len(rows)
        if views[name].dtype.kind == "f":
            csv = np.array([float(r[i]) if r[i] else np.nan for r in rows])
            assert np.allclose(views[name], csv, rtol=1e-8, atol=0, equal_nan=True), name
        elif views[name].dtype.kind == "b":
            assert [str(int(x)) for x in views[name]] == [r[i] for r in rows], name
        else:
            assert [str(x) for x in views[name]] == [r[i] for r in rows], name


def run_greedy(world, seed, **kwargs):
    return canopy.run_mission(world, small_settings(), planner=load_example().coverage_greedy, seed=seed, **kwargs)


def test_python_planner_mission_is_deterministic(world):
    a = run_greedy(world, 1)
    b = run_greedy(world, 1)
    assert a.views_csv == b.views_csv and a.map == b.map
    assert a.summary["method"]["name"] == "python" and a.settings.get("method.name") == "python"
    nbv = a.views["phase"] == "nbv"
    assert np.sum(a.views["success"] & nbv) == 2  # the stop's budget, reached by the Python planner
    assert set(a.views["source"][nbv]) == {"nbv"}
    initial = a.views["phase"] == "initial"
    assert a.sc_curve()["coverage"][-1] > a.views["coverage"][initial][-1]


def test_the_planner_gets_what_builtin_planners_get(world):
    calls, stops = [], []

    class Recorder:
        def begin_stop(self):
            stops.append(len(calls))

        def __call__(self, request):
            calls.append({"taken": request.taken, "budget": request.budget, "stop": request.stop,
                          "region": request.region, "camera": request.camera, "seed": request.seed,
                          "voxels": request.map.counts()["voxels"], "scripted": request.scripted.shape})
            return {"views": [], "reason": "recorded only"}

    # Without the mission's exploration planner an empty answer ends the stop.
    result = canopy.run_mission(world, small_settings(exploration="none"), planner=Recorder(), seed=1)
    initial_ok = result.views["success"] & (result.views["phase"] == "initial")
    assert stops == [0] and len(calls) == 1  # one stop; an empty answer ends it
    call = calls[0]
    reached = result.views["reached_pose"][initial_ok]
    assert np.allclose(call["taken"], reached) and call["budget"] == 2 and call["stop"] == 0
    assert call["voxels"] > 0 and call["scripted"] == (0, 4, 4)
    assert np.allclose(call["camera"], reached[-1], atol=1e-9)
    assert result.stops[0]["end"] == "planner_done" and "recorded only" in result.stops[0]["end_reason"]
    assert np.array_equal(call["region"], canopy.Robot().stop_region(result.stops[0]["goal"]))


def test_the_planner_learns_every_outcome(world):
    told, seen = [], []
    far = np.eye(4)
    far[:3, 3] = [50.0, 0.0, 1.0]  # no IK

    class Learner:
        def outcome(self, o):
            told.append(o)

        def __call__(self, request):
            seen.append((request.outcomes, request.failed, request.is_failed(far)))
            return {"views": [far], "order": "utility"} if len(seen) == 1 else []

    result = canopy.run_mission(world, small_settings(exploration="none"), planner=Learner(), seed=1)
    assert len(told) == len(result.views["attempt"]) == 13
    assert [o["success"] for o in told] == list(result.views["success"])
    assert all(o["success"] == (o["failure"] == "") for o in told)
    assert all(o["phase"] == "initial" and o["reached_pose"].shape == (4, 4) for o in told[:12] if o["success"])
    last = told[-1]
    assert last["failure"] == "no_ik" and last["detail"] and last["reached_pose"] is None and last["phase"] == "nbv"
    assert np.allclose(last["goal_pose"], far) and last["stop"] == 0 and last["attempt"] == 12
    outcomes, failed, is_failed = seen[1]
    assert [o["attempt"] for o in outcomes] == list(range(13)) and outcomes[-1]["failure"] == "no_ik"
    assert failed.shape[1:] == (4, 4) and np.allclose(failed[-1], far) and is_failed
    assert seen[0][0][-1]["attempt"] == 11 and not seen[0][2]


def test_the_mission_fills_the_budget_and_never_retries_a_failed_view(world):
    far = np.eye(4)
    far[:3, 3] = [50.0, 0.0, 1.0]  # no IK: fails for a cause of its own

    def stubborn(request):
        return {"views": [far], "order": "utility"}  # the same view every round, failed or not

    result = canopy.run_mission(world, small_settings(), planner=stubborn, seed=1)
    stop = result.stops[0]
    assert stop["end"] == "budget_met" and stop["successful"] == stop["budget"]
    assert stop["guarded"] >= 1 and stop["exploration_rounds"] >= 1
    nbv = result.views["phase"] == "nbv"
    assert int(np.sum(np.all(np.isclose(result.views["goal_pose"][nbv], far), axis=(1, 2)))) == 1


def test_the_example_runs(tmp_path):
    p = subprocess.run([sys.executable, str(SOURCE / "examples/python/coverage_greedy.py"), "--world",
                        "worlds/small.yaml", "--out", str(tmp_path / "run")], capture_output=True, text=True, cwd=SOURCE)
    assert p.returncode == 0, p.stderr
    summary = json.load(open(tmp_path / "run" / "summary.json"))
    assert summary["method"]["name"] == "python" and summary["views_successful"] > 0
    lines = p.stdout.strip().splitlines()
    assert lines[-1].startswith(f"coverage_greedy: {summary['views_successful']} of {summary['views_attempted']} views")
    assert f"fruit SC {summary['final']['fruit_coverage']:.3f}" in lines[-1]
    assert len(lines) == summary["views_successful"] + 1  # one line per successful view


def test_the_mission_releases_the_gil(world):
    counts, done = [0], threading.Event()

    def count():
        while not done.is_set():
            counts[0] += 1

    thread = threading.Thread(target=count)
    thread.start()
    try:
        canopy.run_mission(world, small_settings(0), seed=1)
    finally:
        done.set()
        thread.join()
    assert counts[0] > 100000, f"the counting thread ran {counts[0]} times during the mission"


INTERRUPTED = """
import sys, canopy
world = canopy.World("worlds/small.yaml")
settings = canopy.Settings().set("mission.loop.views_per_stop", 12)
try:
    canopy.run_mission(world, settings, out=sys.argv[1], progress=lambda line: print(line, flush=True))
except KeyboardInterrupt:
    print("KeyboardInterrupt", flush=True)
    sys.exit(3)
"""


def test_ctrl_c_stops_the_mission_and_keeps_the_partial_run(tmp_path):
    p = subprocess.Popen([sys.executable, "-c", INTERRUPTED, str(tmp_path / "run")], stdout=subprocess.PIPE,
                         text=True, cwd=SOURCE)
    lines = []
    for line in p.stdout:
        lines.append(line)
        if "initial view 2 " in line:
            p.send_signal(signal.SIGINT)
            break
    out, _ = p.communicate(timeout=120)
    assert p.returncode == 3 and "KeyboardInterrupt" in out, "".join(lines) + out
    summary = json.load(open(tmp_path / "run" / "summary.json"))
    assert summary["complete"] is False and summary["end_reason"] == "interrupted"
    rows = (tmp_path / "run" / "views.csv").read_text().splitlines()[1:]
    assert 2 <= len(rows) < 24 and summary["views_attempted"] == len(rows)


def test_ctrl_c_in_the_planner_stops_the_mission(world, tmp_path):
    def interrupted(request):
        raise KeyboardInterrupt  # what Ctrl-C does while Python code runs

    try:
        canopy.run_mission(world, small_settings(), planner=interrupted, out=str(tmp_path / "run"))
        raise AssertionError("no KeyboardInterrupt")
    except KeyboardInterrupt:
        pass
    summary = json.load(open(tmp_path / "run" / "summary.json"))
    assert summary["complete"] is False and summary["stops"][0]["end_reason"] == "interrupted"
    assert summary["views_attempted"] == 12  # the initial scan, then the planner's first call


def test_the_video_is_recorded_and_changes_nothing(world, tmp_path):
    plain = canopy.run_mission(world, small_settings(0), seed=1)
    filmed = canopy.run_mission(world, small_settings(0), seed=1, video=tmp_path / "run.mp4", video_size=(128, 96),
                                video_fps=4)
    assert filmed.views_csv == plain.views_csv
    assert filmed.summary["video"]["frames"] > 10 and (tmp_path / "run.mp4").stat().st_size > 1000
    probe = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
                            "stream=codec_name,width,height", "-of", "csv=p=0", str(tmp_path / "run.mp4")],
                           capture_output=True, text=True)
    assert probe.stdout.strip() == "h264,128,96"
