"""Issue 31 from Python: numbers are read and written the same under a comma-decimal locale,
an empty key path is a ValueError (not a crash), integer depth needs its unit, and a bad
CANOPY_DATA_DIR is named in the error."""

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import canopy
from conftest import SOURCE, look_at, pose7


@pytest.fixture(scope="module")
def comma_locale(tmp_path_factory):
    """The environment of a child process with de_DE.UTF-8 (decimal comma), compiled into a
    temporary folder (LOCPATH) so the test does not depend on the locales installed."""
    localedef = shutil.which("localedef")
    assert localedef, "localedef (package locales / libc-bin) is needed to build a comma-decimal locale"
    folder = tmp_path_factory.mktemp("locales")
    subprocess.run([localedef, "-c", "-i", "de_DE", "-f", "UTF-8", str(folder / "de_DE.UTF-8")], capture_output=True)
    assert (folder / "de_DE.UTF-8").is_dir(), "localedef did not build de_DE.UTF-8"
    env = dict(os.environ)
    env["LOCPATH"] = str(folder)
    return env


CHILD = r"""
import json, locale, sys
import canopy
locale.setlocale(locale.LC_ALL, "de_DE.UTF-8")
assert locale.localeconv()["decimal_point"] == ",", locale.localeconv()["decimal_point"]
folder, frames = sys.argv[1], sys.argv[2]
s = canopy.Settings().set("mission.loop.views_per_stop", 1).set("mapping.extractor.p_gt", 0.7)
s.save(folder + "/settings.yaml")
text = open(folder + "/settings.yaml").read()
assert "p_gt: 0.7" in text and "0,7" not in text, [l for l in text.splitlines() if "p_gt" in l]
assert canopy.Settings(folder + "/settings.yaml") == s
world = canopy.World("worlds/small.yaml")
result = canopy.run_mission(world, s, seed=1, out=folder + "/run")
rows = result.views_csv.splitlines()
header = rows[0].split(",")
assert len(rows) > 1 and all(len(r.split(",")) == len(header) for r in rows), rows[:3]
assert open(folder + "/run/views.csv").read() == result.views_csv
recorded = canopy.read_frames(frames)
assert len(recorded["frames"]) == 1 and recorded["skipped"] == [], recorded["skipped"]
print(json.dumps({"views_csv": result.views_csv}))
"""


def test_numbers_do_not_depend_on_the_locale(comma_locale, cli, tmp_path):
    """Item 1: after locale.setlocale(LC_ALL, 'de_DE.UTF-8') every number canopy writes has a
    decimal point, and what it reads (settings, TUM timestamps) reads the same."""
    pose = pose7(look_at([0.0, -0.25, 0.65], [0.0, 0.75, 0.6]))
    cli("render", "--world", "worlds/small.yaml", "--camera-pose", pose, "--out", tmp_path / "seq")
    tum = tmp_path / "tum"
    (tum / "rgb").mkdir(parents=True)
    (tum / "depth").mkdir()
    shutil.copy(tmp_path / "seq" / "rgb.png", tum / "rgb" / "1.png")
    shutil.copy(tmp_path / "seq" / "depth.png", tum / "depth" / "1.png")
    (tum / "camera.yaml").write_text("width_px: 400\nheight_px: 400\nfx_px: 381.36\nfy_px: 381.36\ncx_px: 200\n"
                                     "cy_px: 200\ndepth_scale_per_m: 1000\n")
    (tum / "rgb.txt").write_text("# rgb\n1.5 rgb/1.png\n")
    (tum / "depth.txt").write_text("1.501 depth/1.png\n")
    (tum / "groundtruth.txt").write_text("1.5 0 0 0.6 0.5 0.5 0.5 0.5\n")
    p = subprocess.run([sys.executable, "-c", CHILD, str(tmp_path), str(tum)], env=comma_locale, cwd=SOURCE,
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr[-2000:]
    # The same mission in the "C" locale writes the same bytes.
    s = canopy.Settings().set("mission.loop.views_per_stop", 1).set("mapping.extractor.p_gt", 0.7)
    plain = canopy.run_mission(canopy.World("worlds/small.yaml"), s, seed=1)
    import json
    assert json.loads(p.stdout.splitlines()[-1])["views_csv"] == plain.views_csv


def test_an_empty_key_path_is_a_value_error():
    """Item 2: set('') and update({'': 3}) crashed the interpreter (exit 139)."""
    s = canopy.Settings()
    for call in (lambda: s.set("", 1), lambda: s.update({"": 3}), lambda: s.set("mission.", 1)):
        with pytest.raises(ValueError) as e:
            call()
        assert "key path" in str(e.value)
    assert s == canopy.Settings()


def test_integer_depth_needs_its_unit(world):
    """Item 16: uint16 millimetres were taken as metres (points 1000 times too far)."""
    pose = world.views("aisle")[2]
    rendered = world.render(pose)
    mm = np.round(rendered.depth * 1000.0).astype(np.uint16)
    with pytest.raises(ValueError) as e:
        canopy.Frame(mm, rendered.pose, rendered.intrinsics, labels=rendered.labels)
    assert "depth_scale" in str(e.value) and "uint16" in str(e.value)
    with pytest.raises(ValueError):
        canopy.Frame(mm, rendered.pose, rendered.intrinsics, depth_scale=-1.0)
    scaled = canopy.Frame(mm, rendered.pose, rendered.intrinsics, labels=rendered.labels, depth_scale=0.001)
    assert np.allclose(scaled.depth, rendered.depth, atol=0.0006)
    settings = canopy.Settings().set("mapping.extractor.source", "truth")
    a, b = canopy.Map(settings, classes=world), canopy.Map(settings, classes=world)
    a.insert(rendered)
    b.insert(scaled)
    # The same map within the millimetre rounding, and not the empty one.
    empty = canopy.Map(settings, classes=world).metrics(world)["total_entropy"]
    ea, eb = a.metrics(world)["total_entropy"], b.metrics(world)["total_entropy"]
    assert eb == pytest.approx(ea, rel=0.02) and abs(ea - empty) > 1.0, (ea, eb, empty)


@pytest.mark.parametrize("value", ["nowhere", "", "file"])
def test_a_bad_data_dir_is_named(tmp_path, value):
    """Item 17: a CANOPY_DATA_DIR that names no data folder is named in the error."""
    if value == "file":
        (tmp_path / "file").write_text("x")
    env = dict(os.environ)
    env["CANOPY_DATA_DIR"] = str(tmp_path / value) if value else ""
    # Run from a folder without canopy's data, with a copy of the module outside the build
    # tree so nothing finds the data beside it.
    module = tmp_path / "mod" / "canopy"
    shutil.copytree(os.path.dirname(canopy.__file__), module)
    for pointer in module.parent.glob("canopy-data-dir"):
        pointer.unlink()
    env["PYTHONPATH"] = str(module.parent)
    p = subprocess.run([sys.executable, "-c", "import canopy; canopy.Settings()"], env=env, cwd=tmp_path,
                       capture_output=True, text=True)
    assert p.returncode != 0
    assert "CANOPY_DATA_DIR" in p.stderr.splitlines()[-1], p.stderr[-500:]
