#!/usr/bin/env python3
"""Tests mirror the sources both ways (docs/development.md).

1. Every C++ test file is tests/<module>/<unit>_test.cpp, or <unit>_<aspect>_test.cpp, for a
   source unit of that module: src/<module>/.../<unit>.cpp or include/canopy/<module>/.../<unit>.h.
   tests/cli tests the command line tool, whose units are tools/cmd_<command>.cpp; tests/support
   holds the test main.
2. Every library unit src/<module>/.../<unit>.cpp has its own test file
   tests/<module>/<unit>_test.cpp (or <unit>_<aspect>_test.cpp), unless ALLOWED lists it with a
   one-line reason. An entry of ALLOWED whose unit is gone or has its own test file now is a
   problem too, so the list only shrinks."""
import pathlib
import sys

ROOT = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")

# Units without a test file of their own, each with the reason (module/unit: reason).
ALLOWED = {
    "common/data_dir": "the data folder's search order, exercised by every test that loads worlds/ or configs/ (find_data_file)",
    "common/interrupt": "signal handlers of the process: cli.interrupt sends SIGINT and SIGTERM to every long command",
    "datasets/sequence_mapping": "mapping a recorded sequence: frame_io_round_trip_test.cpp (RecordedFrames) maps files against memory",
    "evaluation/segmentation_check": "the colour check of imported plants: world_job_test.cpp and cli.world_checks",
    "experiments/ablation_runner": "the free-camera ablation's runner: ablation_test.cpp and nbv_ablate_smoke",
    "experiments/experiment_report": "experiment_test.cpp (ExperimentReport); split out once issue 46 points 7 and 8 settle experiments/",
    "experiments/experiment_run": "experiment_test.cpp (ExperimentRun: failed, killed and damaged trials, resume)",
    "experiments/report_groups": "the report's grouping of trials: experiment_test.cpp (ExperimentReport.AggregatesKnownValues)",
    "jobs/ablation_job": "a job over experiments/ablation_runner: nbv_ablate_smoke runs it through canopy ablate",
    "jobs/bench_compare": "canopy bench mission --against / --save: cli.bench_mission",
    "jobs/bench_gain": "canopy bench gain: a timing benchmark over nbv/gains (gains_test.cpp holds the properties)",
    "jobs/experiment_page": "report.html of an experiment: experiment_cli_test.sh and run_report_browser_test.sh",
    "jobs/map_job": "canopy map: recorded_map_job_test.cpp and cli.frames",
    "jobs/test_views": "the held-out views of a dataset export: nerfstudio_test.cpp",
    "jobs/visibility_job": "canopy visibility: visibility_test.cpp tests the protocol it runs",
    "mapping/frame_mapping": "one frame into the map (14 lines over insertion): color_segmentation_render_test.cpp",
    "mission/mission_stop": "the stop's part of Mission: mission_test.cpp and mission_loop_test.cpp",
    "mission/candidate_audit": "oracle_planners_test.cpp (Oracle.CandidateAuditScoresEveryCandidateByEveryGainAndTheTruth)",
    "mission/scan_pipeline": "the mission's second thread: mission_test.cpp (OverlappedMovesGiveTheSameViewsAsMovesInLine, IncrementalMetrics...)",
    "mission/stepping": "stepping and driving the robot: mission_test.cpp (MissionFaults) and simulator_motion_test.cpp",
    "motion/arm_search": "OMPL's side of ArmPlanner (a private header): arm_planner_test.cpp (seeded plans, motion checks on several threads, the iteration budget, every planner of the registry)",
    "motion/robot_model": "ur_kinematics_test.cpp (RobotModel.CollisionBodiesAndAdjacency, the FK and IK through the model)",
    "motion/view_reach": "the reach test of a view: cmd_nbv_test.cpp and reach_job_test.cpp",
    "nbv/fruit_shapes": "shape_test.cpp (FruitShapes.FrontScanPredictsTheBackHalf)",
    "records/records": "the records' vocabularies, being given visit() by issue 46 point 1: view_columns_test.cpp, run_folder_test.cpp",
    "records/schema": "the records' visit() names: every output against it in python/tests/test_records.py (views.csv, summary.json, report data, on_view, bags), view_columns_test.cpp",
    "ros2/mcap_blocks": "McapReader's data section (a private unit of the reader): mcap_reader_test.cpp (a file without summary scanned, every cut, every flipped byte, overlapping chunks)",
    "ros2/mcap_input": "McapReader's file input (a private header): mcap_reader_test.cpp (a missing file, a folder, a device, every cut)",
    "ros2/mcap_records": "MCAP record framing internal to the writer and reader (a private header): mcap_writer_test.cpp and mcap_reader_test.cpp (every cut, every flipped byte, CRCs)",
    "world/plant_folder": "imported plant folders: plant_import_test.cpp and cli.import_plant",
    "world/plant_generator": "procedural plants: world_test.cpp (WorldGeneration)",
    "world/plant_scene": "assimp's reading of a model: plant_import_test.cpp and cli.textured_plant",
    "world/texture": "plant textures: plant_import_test.cpp and cli.textured_plant",
}


def units(module):
    if module == "cli":
        return {p.stem for p in (ROOT / "tools").glob("*.cpp")}
    found = {p.stem for p in (ROOT / "src" / module).rglob("*.cpp")}
    return found | {p.stem for p in (ROOT / "include" / "canopy" / module).rglob("*.h")}


def tested(stem, test_stems):
    return any(t == stem or t.startswith(stem + "_") for t in test_stems)


problems = []
tests = sorted(p for p in (ROOT / "tests").rglob("*.cpp") if p.relative_to(ROOT / "tests").parts[0] != "support")
test_stems = {}  # module -> stems of its test files
for t in tests:
    module = t.relative_to(ROOT / "tests").parts[0]
    if not t.name.endswith("_test.cpp"):
        problems.append(f"{t.relative_to(ROOT)}: not named <unit>_test.cpp")
        continue
    stem = t.name[: -len("_test.cpp")]
    test_stems.setdefault(module, set()).add(stem)
    if not any(stem == u or stem.startswith(u + "_") for u in units(module)):
        problems.append(f"{t.relative_to(ROOT)}: no source unit '{stem}' in module {module}")

sources = sorted((ROOT / "src").rglob("*.cpp"))
listed = set()
for s in sources:
    key = f"{s.relative_to(ROOT / 'src').parts[0]}/{s.stem}"
    has_test = tested(s.stem, test_stems.get(key.split("/")[0], set()))
    if key in ALLOWED:
        listed.add(key)
        if has_test:
            problems.append(f"{s.relative_to(ROOT)}: has its test file now; take '{key}' off the allow list")
    elif not has_test:
        problems.append(f"{s.relative_to(ROOT)}: no test file tests/{key.split('/')[0]}/{s.stem}_test.cpp "
                        "(write one, or list the unit in ALLOWED with a reason)")
for key in sorted(set(ALLOWED) - listed):
    problems.append(f"allow list: '{key}' is no source unit")
for key, reason in ALLOWED.items():
    if not reason.strip() or "\n" in reason:
        problems.append(f"allow list: '{key}' needs a one-line reason")
for p in problems:
    print(p)
print(f"tests mirror: {len(problems)} problem(s) in {len(tests)} test files and {len(sources)} units "
      f"({len(listed)} allowed without a test file)")
sys.exit(1 if problems else 0)
