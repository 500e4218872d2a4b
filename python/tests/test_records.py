"""One schema for every record (records.h, schema.h): each output of a mission names the fields
the schema declares, with the same names: views.csv's header, MissionResult.views, on_view's
dict, summary.json (and its stops), and the report's data in report.html (its views, stops and
vocabulary). The bag writer's view records are held to it in test_bags.py."""

import csv
import io
import json
import re

import numpy as np

import canopy


def report_data(folder):
    html = (folder / "report.html").read_text()
    block = re.search(r'<script id="canopy-data" type="application/json">(.*?)</script>', html, re.S).group(1)
    return json.loads(block.replace("\\u003c", "<"))


def summary_keys(fields, prefix):
    """The keys at one level of summary_fields() (prefix '' for the top, 'stops[].' for a stop's)."""
    out = set()
    for f in fields:
        name = f["name"]
        if name.startswith(prefix) and "." not in name[len(prefix):] and "[]" not in name[len(prefix):]:
            out.add(name[len(prefix):])
    return out


def test_every_output_names_the_schemas_fields(world, tmp_path):
    fields = canopy.view_fields()
    names = [f["name"] for f in fields]
    csv_names = [f["name"] for f in fields if f["in_views_csv"]]
    known = [f["name"] for f in fields if f["known_when_taken"]]
    assert len(set(names)) == len(names) and names[: len(csv_names)] == csv_names
    assert {"goal_pose", "reached_pose", "target", "message"} <= set(names) - set(csv_names)
    assert "coverage" not in known and "attempt" in known
    seen = []
    settings = canopy.Settings().set("mission.loop.views_per_stop", 1).set("mission.scan.azimuths_deg", [0])
    result = canopy.run_mission(world, settings, seed=1, out=str(tmp_path / "run"),
                                on_view=lambda d: seen.append(sorted(k for k in d if k in names)))
    # views.csv, Python's views, on_view.
    header = next(csv.reader(io.StringIO(result.views_csv)))
    assert header == csv_names
    assert list(result.views) == names
    assert all(len(result.views[n]) == len(result.views["attempt"]) for n in names)
    assert seen and all(keys == sorted(known) for keys in seen)
    # summary.json: its keys (present-only ones may be absent) and its stops'.
    sfields = canopy.summary_fields()
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    top = summary_keys(sfields, "")
    assert set(summary) <= top and top - set(summary) <= {"zero_coverage_reason", "video"}
    assert set(summary["stops"][0]) == summary_keys(sfields, "stops[].")
    assert set(summary["motion_cost"]) == summary_keys(sfields, "motion_cost.")
    # The report's data: the views by the same names, the stops as summary.json has them, the vocabulary.
    data = report_data(tmp_path / "run")
    assert sorted(data["views"]) == sorted(names)  # a JSON object: its keys in name order
    assert data["views"]["attempt"] == list(result.views["attempt"])
    assert data["views"]["coverage"] == [float(f"{c:.9g}") for c in result.views["coverage"]]
    assert data["stops"] == summary["stops"]
    assert data["vocabulary"] == canopy.vocabulary()


def test_vocabularies_are_the_libraries(world):
    v = canopy.vocabulary()
    assert [p["name"] for p in v["view_phases"]] == ["initial", "nbv", "predefined", "view"]
    assert all(re.fullmatch(r"#[0-9a-f]{6}", p["colour"]) for p in v["view_phases"])
    assert "no_ik" in v["failure_causes"] and "" not in v["failure_causes"]
    paper = [c["name"] for c in v["plot_categories"] if c["paper"]]
    assert paper == ["mapping", "nbv_planning", "motion_planning", "control"]
    every = {p for c in v["plot_categories"] for p in c["phases"]}
    assert every <= set(v["wall_phases"])
    # A mission's wall-time phases are the vocabulary's.
    result = canopy.run_mission(world, canopy.Settings().set("mission.loop.views_per_stop", 1), seed=1)
    assert set(result.summary["wall_time_by_phase_s"]) <= set(v["wall_phases"])
    assert set(np.unique(result.views["failure"])) <= set(v["failure_causes"]) | {""}
