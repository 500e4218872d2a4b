"""Ctrl-C (SIGINT) and SIGTERM, sent to real processes at two moments: early (right after the
work starts) and mid-work (after a progress line showing work done: a mapped frame, a view).
Each command keeps what it promises (docs/python.md#what-the-module-holds): map-bag and
run_mission(out=) publish the work so far marked incomplete, or nothing when nothing was done;
export-bag leaves no bag and no hidden partial file; the exit code is 128 + the signal."""

import json
import os
import re
import signal
import subprocess
import sys

import pytest

from conftest import SOURCE
from test_bags import write_long_bag

SIGNALS = [signal.SIGINT, signal.SIGTERM]
MOMENTS = ["early", "mid"]


def interrupt(args, pattern, sig):
    """Runs args (stdout and stderr merged), sends `sig` when a line matches `pattern`; returns
    the exit code and the lines."""
    p = subprocess.Popen([str(a) for a in args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                         cwd=SOURCE, bufsize=1)
    lines, sent = [], False
    try:
        for line in p.stdout:
            lines.append(line.rstrip("\n"))
            if not sent and re.search(pattern, line):
                p.send_signal(sig)
                sent = True
        code = p.wait(timeout=120)
    finally:
        if p.poll() is None:
            p.kill()
    assert sent, "the moment never came:\n" + "\n".join(lines)
    return code, lines


def leftovers(folder):
    """What an interrupted command must not leave: hidden files (a bag's .NAME.partial), a staged
    DIR.partial, lock files."""
    return sorted(n for n in os.listdir(folder) if n.startswith(".") or n.endswith((".partial", ".lock")))


@pytest.fixture(scope="module")
def long_bag(tmp_path_factory):
    """120 frames of 640 x 480: mapping takes seconds, so mid-work is mid-work."""
    path = tmp_path_factory.mktemp("long") / "long.bag"
    write_long_bag(path, 120)
    return path


@pytest.mark.parametrize("sig", SIGNALS, ids=lambda s: s.name)
@pytest.mark.parametrize("moment", MOMENTS)
def test_map_bag(long_bag, tmp_path, sig, moment):
    pattern = r"^read " if moment == "early" else r"^frame \S+: \d+ points"
    code, lines = interrupt([sys.executable, "-m", "canopy", "map-bag", long_bag, "--out", tmp_path / "out", "--rgb",
                             "/cam/rgb", "--depth", "/cam/depth", "--camera-info", "/cam/info"], pattern, sig)
    assert code == 128 + sig, lines
    assert leftovers(tmp_path) == []
    if not (tmp_path / "out").exists():  # nothing mapped yet (before or in the first frame): nothing written
        assert moment == "early", lines
        assert lines[-1] in ("canopy: interrupted; nothing was written",
                             "canopy: interrupted before the first frame; nothing was written"), lines
        return
    record = json.loads((tmp_path / "out" / "frames.json").read_text())
    assert record["complete"] is False and 1 <= record["frames_mapped"] < 120, lines
    assert lines[-1].startswith(f"canopy: interrupted after {record['frames_mapped']} frames; the map so far is saved")


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    """A finished `canopy mission` run folder of the small world (an initial scan of 4 views and
    2 more)."""
    tmp = tmp_path_factory.mktemp("run")
    p = subprocess.run([os.environ["CANOPY_CLI"], "mission", "--world", "worlds/small.yaml", "--seed", "2", "--set",
                        "mission.loop.views_per_stop=2", "--set", "mission.scan.azimuths_deg=[0]", "--no-report",
                        "--out", tmp / "run"], capture_output=True, text=True, cwd=SOURCE)
    assert p.returncode == 0, p.stderr
    return tmp / "run"


@pytest.mark.parametrize("sig", SIGNALS, ids=lambda s: s.name)
@pytest.mark.parametrize("moment", MOMENTS)
def test_export_bag(run_dir, tmp_path, sig, moment):
    pattern = r"^replaying " if moment == "early" else r"view \d+ ok"
    code, lines = interrupt([sys.executable, "-m", "canopy", "export-bag", run_dir, tmp_path / "run.bag"], pattern,
                            sig)
    assert code == 128 + sig, lines
    assert lines[-1] == "canopy: interrupted; no bag written", lines
    assert os.listdir(tmp_path) == []


MISSION = """
import sys, canopy
if sys.argv[2] == "handled":
    canopy.stop_on_sigterm()
world = canopy.World("worlds/small.yaml")
settings = canopy.Settings().update({"mission.loop.views_per_stop": 2, "mission.scan.azimuths_deg": [0]})
try:
    print("start", file=sys.stderr, flush=True)
    canopy.run_mission(world, settings, seed=2, out=sys.argv[1], report=False,
                       progress=lambda line: print(line, file=sys.stderr, flush=True))
except KeyboardInterrupt as e:
    print(f"KeyboardInterrupt: {e}", file=sys.stderr, flush=True)
    sys.exit(canopy.interrupts.exit_code())
"""


@pytest.mark.parametrize("sig", SIGNALS, ids=lambda s: s.name)
@pytest.mark.parametrize("moment", MOMENTS)
def test_run_mission(tmp_path, sig, moment):
    """From a script that calls canopy.stop_on_sigterm(): SIGTERM saves as Ctrl-C does."""
    pattern = r"^start" if moment == "early" else r"view \d+ ok"
    code, lines = interrupt([sys.executable, "-c", MISSION, tmp_path / "out", "handled"], pattern, sig)
    assert code == 128 + sig, lines
    assert leftovers(tmp_path) == []
    if not (tmp_path / "out").exists():  # stopped before the first view: nothing written
        assert moment == "early", lines
        return
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["complete"] is False, lines
    assert lines[-1] == "KeyboardInterrupt: mission interrupted; the results so far are in the out folder", lines


def test_run_mission_sigterm_without_a_handler(tmp_path):
    """Python's default for SIGTERM ends the process at once: no summary, the staged folder left
    as out.partial (the next run on out removes it), as docs/python.md says."""
    code, lines = interrupt([sys.executable, "-c", MISSION, tmp_path / "out", "default"], r"view \d+ ok",
                            signal.SIGTERM)
    assert code == -signal.SIGTERM, lines
    assert not (tmp_path / "out").exists() and (tmp_path / "out.partial").is_dir()
