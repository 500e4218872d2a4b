"""Maps from Python: byte-for-byte round trips against `canopy map` (rendered views and
recorded frames), files, bulk voxel queries on a hand-built map, metrics, array lifetimes."""

import gc
import json

import numpy as np

import canopy
from conftest import look_at, pose7

RES = 0.015  # the default voxel edge (configs/mapping.yaml)
ORIGIN = np.array([0.07, 0.07, 1.0])


def test_map_of_rendered_views_equals_the_cli_map(world, cli, tmp_path):
    """The default settings (colour segmentation, seeded segmentation noise): same frames, same bytes."""
    cli("map", "--world", "worlds/small.yaml", "--views", "aisle", "--out", tmp_path / "m")
    m = canopy.Map(classes=world)
    for pose in world.views("aisle"):
        m.insert(world.render(pose))
    assert m.to_bytes() == (tmp_path / "m" / "map.csm").read_bytes()
    expected = json.load(open(tmp_path / "m" / "metrics.json"))
    metrics = m.metrics(world)
    assert metrics["coverage"] == expected["coverage"] and metrics["total_entropy"] == expected["total_entropy"]


def test_map_of_recorded_frames_equals_the_cli_map(world, cli, tmp_path):
    """Frames `canopy render` wrote, read back and inserted with true labels, as `canopy map --frames --seg truth`
    (without mask noise: recorded labels are taken as they are)."""
    for k, x in enumerate([-0.1, 0.1]):
        pose = pose7(look_at([x, -0.25, 0.65], [x, 0.75, 0.6]))
        cli("render", "--world", "worlds/small.yaml", "--camera-pose", pose, "--out", tmp_path / "frames" / f"f{k}")
    p = cli("map", "--frames", tmp_path / "frames", "--seg", "truth", "--out", tmp_path / "m")
    # Recorded labels are taken as they are: no simulated mask noise unless --pgt asks for it,
    # whatever the bundle's p_gt (0.7, the simulator's), and the command says so.
    assert "no simulated mask noise" in p.stderr
    settings = canopy.Settings().set("mapping.extractor.source", "truth").set("mapping.extractor.p_gt", 1)
    recorded = canopy.read_frames(str(tmp_path / "frames"), labels=True)
    assert [f.name for f in recorded["frames"]] == ["f0", "f1"] and recorded["skipped"] == []
    m = canopy.Map(settings, classes=recorded["classes"])
    for frame in recorded["frames"]:
        assert m.insert(frame)["points"] > 0
    assert m.to_bytes() == (tmp_path / "m" / "map.csm").read_bytes()


def test_files_round_trip(world, tmp_path):
    m = canopy.Map(classes=world)
    m.insert(world.render(world.views("aisle")[2]))
    m.save(str(tmp_path / "a.csm"))
    assert (tmp_path / "a.csm").read_bytes() == m.to_bytes()
    loaded = canopy.Map.load(str(tmp_path / "a.csm"))
    assert loaded == m and canopy.Map.from_bytes(m.to_bytes()) == m
    m.save(tmp_path / "b.csm")  # paths as pathlib paths too
    assert canopy.Map.load(tmp_path / "b.csm") == m
    assert loaded.classes == world.classes and loaded.resolution == RES
    assert m.export_ply(str(tmp_path / "a.ply")) == m.counts()["occupied"]
    m.export_bt(str(tmp_path / "a.bt"))
    assert (tmp_path / "a.bt").stat().st_size > 0
    copy = m.copy()
    copy.insert(world.render(world.views("aisle")[3]))
    assert copy != m and canopy.Map.load(str(tmp_path / "a.csm")) == m


def plane_map(hits=1):
    """A 10 x 10 patch of fruit voxels at z = 0.5, seen from above (voxel centres as points)."""
    m = canopy.Map()
    xs = (np.arange(10) + 0.5) * RES
    points = np.array([[x, y, (33 + 0.5) * RES] for x in xs for y in xs])
    labels = np.full(len(points), m.classes.index("fruit"))
    for _ in range(hits):
        m.insert_cloud(points, labels, origin=ORIGIN)
    return m, points


def test_bulk_queries_on_a_hand_built_map():
    m, points = plane_map()
    assert np.all(m.occupancy(points) > 0.5) and np.all(m.known(points))
    assert np.all(m.most_likely_class(points) == m.classes.index("fruit"))
    above = ORIGIN + 0.6 * (points - ORIGIN)  # on the rays: seen free
    assert np.all(m.known(above)) and np.all(m.occupancy(above) < 0.5)
    below = points - [0.0, 0.0, 0.2]  # behind the patch: never observed
    assert not np.any(m.known(below)) and np.all(m.occupancy(below) == 0.5)
    assert np.all(m.most_likely_class(below) == -1)
    h_unknown = m.entropy(below)
    assert np.all(h_unknown == h_unknown[0]) and h_unknown[0] > m.entropy(points).max()
    probs = m.class_probabilities(np.vstack([points, below]))
    assert probs.shape == (200, len(m.classes) + 1) and np.allclose(probs.sum(axis=1), 1.0)
    assert np.allclose(probs[100:, 0], 0.5) and np.all(np.argmax(probs[:100], axis=1) == 1 + m.classes.index("fruit"))
    occ = m.voxels("occupied")
    assert len(occ["center"]) == m.counts()["occupied"] == 100
    assert np.allclose(np.sort(occ["center"], axis=0), np.sort(points, axis=0))
    assert np.allclose(occ["p_occ"], m.occupancy(occ["center"]))
    free = m.voxels("free")
    assert len(free["center"]) == m.counts()["free"] and np.all(free["p_occ"] < 0.5)
    inside = m.voxels("occupied", region=[[0.0, 0.0, 0.4], [0.05, 0.05, 0.6]])
    assert len(inside["center"]) == 9  # 3 x 3 voxel centres below 0.05 m
    assert m.counts()["target"] == 100


def test_arrays_outlive_their_map():
    m, points = plane_map()
    voxels = m.voxels("all")
    occupancy = m.occupancy(points)
    kept = {k: v.copy() for k, v in voxels.items()}
    del m
    gc.collect()
    assert all(np.array_equal(voxels[k], kept[k]) for k in kept) and np.all(occupancy > 0.5)


def test_metrics_against_the_ground_truth(world):
    empty = canopy.Map(classes=world).metrics(world)
    assert empty["coverage"] == 0.0
    m = canopy.Map(canopy.Settings().set("mapping.extractor.p_gt", 1.0), classes=world)
    for pose in world.views("aisle"):
        m.insert(world.render(pose))
    metrics = m.metrics(world)
    assert 0.05 < metrics["coverage"] <= 1.0
    assert len(metrics["fruits"]) == int(np.sum(world.fruits["target"]))
    assert metrics["total_entropy"] < empty["total_entropy"]
