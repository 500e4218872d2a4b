#!/usr/bin/env python3
"""tools/train_view_ranker.py's cross-validation (--cv) and refusals on synthetic candidate audits.

Three tuning worlds, two planners' trials each, rounds of 20 candidates whose truth grows with one
feature ("signal") and ignores the other ("noise"). A model trained on two worlds ranks the third
world's rounds by the signal, so every condition's truth share and Spearman rho are near 1; the
text is the same when run twice (fixed seed). An evaluation world (seed >= 1000) among the runs,
or --cv beside --out, is one line and exit 2. --fruit-maxima trains a model that also names each
feature's fruit maximum (equal to a slow reference), which --model --evaluate reads back;
--drop-features trains on fewer features, and such a model reads a run recording more by name;
--fruit-value writes a fruit-value model beside the ranker, paired with it, read back by --model;
--p-gt keeps the rounds of trials with those segmentation accuracies only.
Usage: train_view_ranker_test.py SOURCE_DIR"""
import csv
import json
import os
import pathlib
import re
import subprocess
import sys
import tempfile

import numpy as np

script = pathlib.Path(sys.argv[1]) / "tools" / "train_view_ranker.py"
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def write_run(root, name, worlds, p_gt=1.0):
    rng = np.random.default_rng(7)
    run = pathlib.Path(root) / name
    for world in worlds:
        for label in ("shape", "learned"):
            trial_id = f"{label}_pgt{p_gt:g}_world{world}_seed1"
            folder = run / "trials" / trial_id
            (folder / "mission").mkdir(parents=True)
            (folder / "trial.json").write_text(json.dumps(
                {"status": "ok", "trial": {"id": trial_id, "label": label, "method": label, "p_gt": p_gt,
                                           "world_seed": world, "seed": 1}}))
            with open(folder / "mission" / "candidates.csv", "w", newline="") as f:
                w = csv.writer(f)
                w.writerow(["stop", "round", "cluster", "planner_gain", "truth", "uvc", "f:signal", "f:noise"])
                for rnd in range(30):
                    signal = rng.uniform(0.0, 1.0, 20)
                    truth = np.round(1000.0 * signal ** 2)
                    for i, (s, t) in enumerate(zip(signal, truth)):
                        w.writerow([0, rnd, i % 4, rng.uniform(), int(t), rng.uniform(), f"{s:.6f}", f"{rng.uniform():.6f}"])
    return str(run)


def run(*args):
    return subprocess.run([sys.executable, str(script), *args], capture_output=True, text=True)


with tempfile.TemporaryDirectory() as tmp:
    runs = write_run(tmp, "synthetic", [1, 2, 3])
    small = ["--trees", "20", "--depth", "3", "--eta", "0.3"]
    first = run(runs, "--cv", *small)
    check(first.returncode == 0, f"--cv exits 0 (got {first.returncode}: {first.stderr.strip()})")
    rows = [l for l in first.stdout.splitlines() if l.startswith("| synthetic |")]
    check(len(rows) == 3, f"one row per planner and 'all' ({len(rows)} rows)")
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        rounds, rho, share = int(cells[3]), float(cells[4]), float(cells[7])
        check(rounds == (90 if cells[2] != "all" else 180), f"{cells[2]}: the rounds of three worlds ({rounds})")
        check(rho > 0.95, f"{cells[2]}: rho {rho} near 1 for a truth that grows with a feature")
        check(share > 0.95, f"{cells[2]}: truth share {share} near 1")
    check(re.search(r"Mean truth share over the conditions: all 0\.9\d\d", first.stdout) is not None,
          "the mean truth share line")
    again = run(runs, "--cv", *small)
    check(again.stdout == first.stdout, "the same text when run twice")
    table = pathlib.Path(tmp) / "cv.md"
    written = run(runs, "--cv", *small, "--table", str(table))
    check(written.returncode == 0 and table.read_text().strip() == first.stdout.strip(), "--table writes the text")

    both = run(runs, "--cv", "--out", str(pathlib.Path(tmp) / "m.json"))
    check(both.returncode == 2 and len(both.stderr.strip().splitlines()) == 1 and "--cv" in both.stderr,
          f"--cv with --out: one line, exit 2 (got {both.returncode}: {both.stderr.strip()})")
    evaluation = write_run(tmp, "evaluation", [1001])
    refused = run(runs, evaluation, "--cv", *small)
    check(refused.returncode == 2 and len(refused.stderr.strip().splitlines()) == 1 and
          "evaluation world" in refused.stderr, f"an evaluation world: one line, exit 2 (got {refused.stderr.strip()})")
    # A learning curve: rank world 1 only, by a model trained on the lowest other world alone.
    curve = run(runs, "--cv", *small, "--cv-hold", "1", "--train-worlds", "1")
    check(curve.returncode == 0 and "(1 by 2)" in curve.stdout,
          f"--cv-hold 1 --train-worlds 1: world 1 by world 2 ({curve.returncode}: {curve.stderr.strip()} {curve.stdout[:200]})")
    curve_rows = [l for l in curve.stdout.splitlines() if l.startswith("| synthetic |") and "| all |" in l]
    check(len(curve_rows) == 1 and int(curve_rows[0].split("|")[4]) == 60,
          f"only world 1's rounds are ranked ({curve_rows})")
    for bad, what in ((["--cv-hold", "7"], "no rounds of world 7"), (["--train-worlds", "3"], "only 2 other worlds")):
        r = run(runs, "--cv", *small, *bad)
        check(r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and what in r.stderr,
              f"{bad}: one line naming it, exit 2 (got {r.returncode}: {r.stderr.strip()})")
    r = run(runs, "--out", str(pathlib.Path(tmp) / "m.json"), "--train-worlds", "1")
    check(r.returncode == 2 and "go with --cv" in r.stderr, f"--train-worlds without --cv refused ({r.stderr.strip()})")
    one = write_run(tmp, "one_world", [1])
    alone = run(one, "--cv", *small)
    check(alone.returncode == 2 and "two tuning worlds" in alone.stderr, f"one world: refused ({alone.stderr.strip()})")

    # --fruit-maxima: each feature's largest value over the round's candidates of the same fruit.
    sys.path.insert(0, str(script.parent))
    import train_view_ranker as tvr
    X = np.array([[1.0, np.nan], [4.0, 2.0], [np.nan, np.nan], [3.0, np.nan], [2.0, 5.0]], dtype=np.float32)
    fruit = np.array([7, 3, 7, 3, 7])
    slow = np.array([[max((X[j, c] for j in range(5) if fruit[j] == fruit[i] and not np.isnan(X[j, c])),
                          default=np.nan) for c in range(2)] for i in range(5)], dtype=np.float32)
    check(np.array_equal(tvr.fruit_maxima(X, fruit), slow, equal_nan=True), "fruit maxima equal the slow reference")
    model = pathlib.Path(tmp) / "fruit.json"
    trained = run(runs, "--fruit-maxima", "--out", str(model), *small)
    names = json.loads(model.read_text())["learner"]["feature_names"] if model.is_file() else []
    check(trained.returncode == 0 and names == ["signal", "noise", "signal@fruit", "noise@fruit"],
          f"--fruit-maxima names the maxima ({trained.returncode}: {names} {trained.stderr.strip()})")
    ranked = run("--model", str(model), "--evaluate", evaluation)
    check(ranked.returncode == 0 and "learned (model)" in ranked.stdout,
          f"--model reads a fruit-maxima model back ({ranked.returncode}: {ranked.stderr.strip()})")

    # --drop-features: a model without "noise" names only "signal" (and its maximum); it reads its
    # features by name from a run that records both, and still ranks by the signal.
    model = pathlib.Path(tmp) / "dropped.json"
    trained = run(runs, "--drop-features", "noise", "--fruit-maxima", "--out", str(model), *small)
    names = json.loads(model.read_text())["learner"]["feature_names"] if model.is_file() else []
    check(trained.returncode == 0 and names == ["signal", "signal@fruit"],
          f"--drop-features noise: the model names signal only ({trained.returncode}: {names} {trained.stderr.strip()})")
    ranked = run("--model", str(model), "--evaluate", evaluation)
    rho = [float(line.split("|")[4]) for line in ranked.stdout.splitlines() if "| learned (model) |" in line]
    check(ranked.returncode == 0 and rho and min(rho) > 0.9,
          f"a model naming fewer features ranks a run by name ({ranked.returncode}: rho {rho} {ranked.stderr.strip()})")
    for bad, what in ((["--drop-features", "nothing"], "no feature nothing"),
                      (["--drop-features", "signal", "noise"], "no feature left")):
        r = run(runs, *bad, "--out", str(pathlib.Path(tmp) / "bad.json"), *small)
        check(r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and what in r.stderr,
              f"{' '.join(bad)}: one line, exit 2 ({r.returncode}: {r.stderr.strip()})")

    # --p-gt: the rounds of trials with those segmentation accuracies only. The same worlds again at
    # P_gt 0.7: --p-gt 1 ranks the first run's rounds alone (its text as without the second run's),
    # --p-gt 0.7 the second's alone, both P_gt every round.
    noisy = write_run(tmp, "noisy", [1, 2, 3], p_gt=0.7)
    clean = run(runs, noisy, "--cv", *small, "--p-gt", "1")
    clean_rows = [l for l in clean.stdout.splitlines() if l.startswith("| ")]
    check(clean.returncode == 0 and clean_rows and all(l.startswith("| synthetic | 1 |") for l in clean_rows[2:]),
          f"--p-gt 1: only P_gt 1's rounds ({clean.returncode}: {clean.stderr.strip()} {clean_rows[:4]})")
    both = run(runs, noisy, "--cv", *small)
    only = run(runs, noisy, "--cv", *small, "--p-gt", "0.7")
    check(any("| noisy | 0.7 |" in l for l in both.stdout.splitlines()) and
          not any("| synthetic |" in l for l in only.stdout.splitlines()) and
          any("| noisy | 0.7 |" in l for l in only.stdout.splitlines()),
          f"--p-gt 0.7: only the noisy run's rounds ({only.returncode}: {only.stderr.strip()})")
    r = run(runs, "--cv", *small, "--p-gt", "0.7")
    check(r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and "no trial with P_gt 0.7" in r.stderr,
          f"--p-gt 0.7 with no such trial: one line, exit 2 ({r.returncode}: {r.stderr.strip()})")

    # --fruit-value: a fruit-value model beside the ranker, paired with it; the ranker reads
    # fruit_value, --model reads both back, and a ranker whose fruit-value model is missing or
    # not its own is refused. The fruit-value model's estimate of a fruit is its best candidate's
    # share of the round's best truth, which grows with the fruit's signal maximum.
    model = pathlib.Path(tmp) / "fv.json"
    trained = run(runs, "--fruit-maxima", "--fruit-value", "--out", str(model), *small)
    fruit_model = pathlib.Path(tmp) / "fv.fruit_value.json"
    ranker = json.loads(model.read_text()) if model.is_file() else {}
    fruit = json.loads(fruit_model.read_text()) if fruit_model.is_file() else {}
    names = ranker.get("learner", {}).get("feature_names", [])
    check(trained.returncode == 0 and names == ["signal", "noise", "signal@fruit", "noise@fruit", "fruit_value"],
          f"--fruit-value: the ranker reads fruit_value ({trained.returncode}: {names} {trained.stderr.strip()})")
    check(fruit.get("learner", {}).get("feature_names") == ["signal@fruit", "noise@fruit"],
          f"the fruit-value model reads the fruit maxima ({fruit.get('learner', {}).get('feature_names')})")
    attrs = ranker.get("learner", {}).get("attributes", {})
    check(attrs.get("canopy_fruit_value") == "fv.fruit_value.json" and attrs.get("canopy_pair") and
          attrs.get("canopy_pair") == fruit.get("learner", {}).get("attributes", {}).get("canopy_pair"),
          f"the ranker names its fruit-value model and both carry the same pair ({attrs})")
    import xgboost as xgb
    fv = xgb.Booster()
    fv.load_model(str(fruit_model))
    lo, hi = fv.predict(xgb.DMatrix(np.array([[0.1, 0.5], [0.9, 0.5]], dtype=np.float32),
                                    feature_names=["signal@fruit", "noise@fruit"]))
    check(hi > lo + 0.3, f"the fruit-value estimate grows with the fruit's signal maximum ({lo:.2f} -> {hi:.2f})")
    ranked = run("--model", str(model), "--evaluate", evaluation)
    rho = [float(line.split("|")[4]) for line in ranked.stdout.splitlines() if "| learned (model) |" in line]
    check(ranked.returncode == 0 and rho and min(rho) > 0.9 and "| fruit_value |" in ranked.stdout,
          f"--model reads the pair back and ranks by the signal ({ranked.returncode}: rho {rho} {ranked.stderr.strip()})")
    cv = run(runs, "--fruit-maxima", "--fruit-value", "--cv", *small)
    check(cv.returncode == 0 and "reading a fruit-value model" in cv.stdout and
          re.search(r"Mean truth share over the conditions: all 0\.9\d\d", cv.stdout) is not None,
          f"--cv with --fruit-value ({cv.returncode}: {cv.stderr.strip()} {cv.stdout[-200:]})")
    other = pathlib.Path(tmp) / "other.json"
    run(runs, "--fruit-maxima", "--fruit-value", "--out", str(other), "--seed", "2", *small)
    unpaired = pathlib.Path(tmp) / "unpaired"
    unpaired.mkdir()
    (unpaired / "fv.json").write_text(model.read_text())
    (unpaired / "fv.fruit_value.json").write_text((pathlib.Path(tmp) / "other.fruit_value.json").read_text())
    alone = pathlib.Path(tmp) / "alone"
    alone.mkdir()
    (alone / "fv.json").write_text(model.read_text())
    for path, what in ((unpaired / "fv.json", "was not trained with the fruit-value model"),
                       (alone / "fv.json", "no such fruit-value model file")):
        r = run("--model", str(path), "--evaluate", evaluation)
        check(r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and what in r.stderr,
              f"{path}: one line, exit 2 ({r.returncode}: {r.stderr.strip()})")
    r = run(runs, "--fruit-value", "--out", str(pathlib.Path(tmp) / "bad.json"), *small)
    check(r.returncode == 2 and "goes with --fruit-maxima" in r.stderr, f"--fruit-value alone refused ({r.stderr.strip()})")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("train_view_ranker: all checks passed")
