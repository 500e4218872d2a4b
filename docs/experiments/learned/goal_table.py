#!/usr/bin/env python3
"""Issue 47's goal table from experiment folders (docs/experiments/learned/README.md).

For each preset folder given (a `canopy experiment` --out folder) and each P_gt: fruit SC after
the 30th, 60th and 90th successful view (a trial that ended before keeps its last figure) and at
the end, mean ± std over the worlds every method completed; the best other map-only method at
each mark (highest mean; the oracle READS THE TRUTH and is a bound, not a method); the method
under test (--method, default learned) against it and against half the way to the oracle after 60
views; paired differences over the worlds (SC points, mean ± paired standard error, wins of n); planning time per
NBV attempt (the planning phases of summary.json over the stops' NBV attempts).

  python3 docs/experiments/learned/goal_table.py default=runs/learned_eval dense=runs/learned_eval_dense
  python3 docs/experiments/learned/goal_table.py dense=docs/experiments/fig3_dense/trials_sc.csv dense=runs/more_worlds
"""
import argparse
import csv
import json
import math
import pathlib
import sys

MARKS = [30, 60, 90]
PLANNING_PHASES = ["clustering", "candidates", "filtering", "scoring", "nbv_planning"]


def stat(xs):
    n = len(xs)
    if n == 0:
        return float("nan"), float("nan")
    m = sum(xs) / n
    s = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1)) if n > 1 else 0.0
    return m, s


def read_trial(folder):
    """(label, p_gt, world, method, figures) of a finished trial folder, or None."""
    tj = folder / "trial.json"
    if not tj.is_file():
        return None
    t = json.loads(tj.read_text())
    if t.get("status") != "ok":
        return None
    spec = t["trial"]
    mission = folder / "mission"
    coverage = []
    sim_time = []
    with open(mission / "views.csv", newline="") as f:
        for row in csv.DictReader(f):
            if row["success"] == "1":
                coverage.append(float(row["coverage"]))
                sim_time.append(float(row["sim_time_s"]))
    if not coverage:
        return None
    summary = json.loads((mission / "summary.json").read_text())
    phases = summary.get("wall_time_by_phase_s", {})
    planning = sum(phases.get(p, 0.0) for p in PLANNING_PHASES)
    attempts = sum(s.get("nbv_attempted", 0) for s in summary.get("stops", []))
    figures = {f"after {k}": coverage[min(len(coverage), k) - 1] for k in MARKS}
    figures["final"] = coverage[-1]
    return {
        "label": spec["label"],
        "method": spec["method"],
        "p_gt": float(spec["p_gt"]),
        "world": spec.get("world_seed"),
        "sc": figures,
        "views": len(coverage),
        "sim_time_s": summary.get("simulated_time_s", sim_time[-1]),
        "planning_s": planning,
        "nbv_attempts": attempts,
        "exploration_rounds": summary.get("exploration_rounds", 0),
    }


def load_csv(path):
    """The trials of a per-trial file that --csv wrote (e.g. docs/experiments/fig3_dense/trials_sc.csv)."""
    trials = []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            trials.append({
                "label": row["label"],
                "method": row["label"],
                "p_gt": float(row["p_gt"]),
                "world": int(row["world_seed"]),
                "sc": {m: float(row["sc_" + m.replace(" ", "_")]) for m in ["after 30", "after 60", "after 90", "final"]},
                "views": int(row["views"]),
                "sim_time_s": float(row["simulated_s"]),
                "planning_s": float(row["planning_s"]),
                "nbv_attempts": int(row["nbv_attempts"]),
            })
    return trials


def load(source):
    """The finished trials of an experiment folder, or of a per-trial .csv file."""
    path = pathlib.Path(source)
    if path.is_file():
        return load_csv(path)
    if not (path / "trials").is_dir():
        sys.exit(f"goal_table: '{source}' is neither an experiment folder nor a per-trial .csv")
    trials = []
    for d in sorted((path / "trials").iterdir()):
        t = read_trial(d)
        if t:
            trials.append(t)
    return trials


def paired(xs):
    """Mean and standard error of per-world differences (the paired SE: std / sqrt(n))."""
    m, s = stat(xs)
    return m, s / math.sqrt(len(xs)) if xs else float("nan")


def pm(m, s, fmt="%.3f"):
    return (fmt % m) + " ± " + (fmt % s)


def condition_tables(preset, p_gt, trials, under_test, out):
    ts = [t for t in trials if abs(t["p_gt"] - p_gt) < 1e-9]
    labels = sorted({t["label"] for t in ts}, key=lambda l: (l != under_test, l.startswith("oracle"), l))
    by = {(t["label"], t["world"]): t for t in ts}
    worlds = sorted(w for w in {t["world"] for t in ts} if all((l, w) in by for l in labels))
    if under_test not in labels or not worlds:
        out.append(f"{preset}, P_gt {p_gt:g}: no worlds every method completed\n")
        return None
    marks = [f"after {k}" for k in MARKS] + ["final"]
    out.append(f"**{preset}, P_gt {p_gt:g}** ({len(worlds)} worlds every method completed: "
               f"{', '.join(str(w) for w in worlds)})\n")
    out.append("| method | SC after 30 | after 60 | after 90 | final | views | simulated time [s] |")
    out.append("|---|---|---|---|---|---|---|")
    means = {}
    for l in labels:
        row = [l + (" (reads the truth)" if l.startswith("oracle") else "")]
        for m in marks:
            mean, sd = stat([by[(l, w)]["sc"][m] for w in worlds])
            means[(l, m)] = mean
            row.append(pm(mean, sd))
        row.append("%.1f" % stat([by[(l, w)]["views"] for w in worlds])[0])
        row.append("%.0f" % stat([by[(l, w)]["sim_time_s"] for w in worlds])[0])
        out.append("| " + " | ".join(row) + " |")
    out.append("")
    others = [l for l in labels if l != under_test and not l.startswith("oracle")]
    if not others:
        out.append(f"(no other map-only method in {preset}, P_gt {p_gt:g}: no goal to check)\n")
        return None
    verdict = {}
    goal_cells = {}
    lines = []
    diffs = []
    for m in marks:
        best = max(others, key=lambda l: means[(l, m)])
        d = [100.0 * (by[(under_test, w)]["sc"][m] - by[(best, w)]["sc"][m]) for w in worlds]
        dm, ds = paired(d)
        wins = sum(1 for x in d if x > 0)
        met = means[(under_test, m)] >= means[(best, m)]
        verdict[m] = met
        goal_cells[m] = (f"{means[(under_test, m)]:.3f} vs {means[(best, m)]:.3f} {best}, "
                    f"{dm:+.1f} ± {ds:.1f} ({wins}) " + ("✔" if met else "✘")).replace("-", "−")
        lines.append(f"{m}: {means[(under_test, m)]:.3f} vs {best} {means[(best, m)]:.3f} "
                     + ("met" if met else f"**not met** by {100 * (means[(best, m)] - means[(under_test, m)]):.1f} points"))
        diffs.append((m, best, f"{dm:+.1f} ± {ds:.1f} ({wins})"))
    half = None
    if "oracle" in labels:
        best60 = max(others, key=lambda l: means[(l, "after 60")])
        half = means[(best60, "after 60")] + 0.5 * (means[("oracle", "after 60")] - means[(best60, "after 60")])
        met = means[(under_test, "after 60")] >= half
        verdict["half way"] = met
        goal_cells["half way"] = (f"{means[(under_test, 'after 60')]:.3f} vs {half:.3f} "
                             + ("✔" if met else f"✘ {100 * (means[(under_test, 'after 60')] - half):+.1f}")).replace("-", "−")
        lines.append(f"half way to the oracle after 60: {means[(under_test, 'after 60')]:.3f} vs {half:.3f} "
                     + ("met" if met else f"**not met** by {100 * (half - means[(under_test, 'after 60')]):.1f} points"))
    out.append(f"{under_test} against the best other map-only method at each mark: " + "; ".join(lines) + ".\n")
    out.append(f"| paired, SC points, mean ± paired SE (wins of {len(worlds)}) | after 30 | after 60 | after 90 | final |")
    out.append("|---|---|---|---|---|")
    out.append(f"| {under_test} − the best other at the mark | " + " | ".join(f"{d} ({b})" for _, b, d in diffs) + " |")
    for l in labels:
        if l == under_test:
            continue
        cells = []
        for m in marks:
            d = [100.0 * (by[(under_test, w)]["sc"][m] - by[(l, w)]["sc"][m]) for w in worlds]
            dm, ds = paired(d)
            cells.append(f"{dm:+.1f} ± {ds:.1f} ({sum(1 for x in d if x > 0)})")
        out.append(f"| {under_test} − {l} | " + " | ".join(cells) + " |")
    out.append("")
    return {"verdict": verdict, "cells": goal_cells, "labels": labels, "worlds": worlds, "by": by}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folders", nargs="+",
                    help="preset=experiment folder or per-trial .csv; a preset given again adds its trials "
                         "(a (label, P_gt, world) given twice is refused)")
    ap.add_argument("--method", default="learned", help="the method under test (a label)")
    ap.add_argument("--csv", action="append", default=[],
                    help="preset=file: write that preset's per-trial figures (the data of a later paired comparison)")
    a = ap.parse_args()
    csv_out = dict(c.partition("=")[::2] for c in a.csv)
    out = []
    timing = []
    summary = []
    sources = {}
    for spec in a.folders:
        preset, _, folder = spec.partition("=")
        if not folder:
            sys.exit(f"goal_table: '{spec}': give preset=folder")
        sources.setdefault(preset, []).append(folder)
    for preset, folders in sources.items():
        trials = []
        seen = set()
        for folder in folders:
            for t in load(folder):
                key = (t["label"], t["p_gt"], t["world"])
                if key in seen:
                    sys.exit(f"goal_table: {preset}: {key} is in two sources")
                seen.add(key)
                trials.append(t)
        if preset in csv_out:
            with open(csv_out[preset], "w", newline="") as f:
                w = csv.writer(f)
                w.writerow(["label", "p_gt", "world_seed", "sc_after_30", "sc_after_60", "sc_after_90", "sc_final",
                            "views", "simulated_s", "planning_s", "nbv_attempts"])
                for t in sorted(trials, key=lambda t: (t["label"], -t["p_gt"], t["world"])):
                    w.writerow([t["label"], f"{t['p_gt']:g}", t["world"]] + [f"{t['sc'][m]:.6f}" for m in
                               ["after 30", "after 60", "after 90", "final"]] +
                               [t["views"], f"{t['sim_time_s']:.3f}", f"{t['planning_s']:.3f}", t["nbv_attempts"]])
        for p in sorted({t["p_gt"] for t in trials}, reverse=True):
            r = condition_tables(preset, p, trials, a.method, out)
            if r:
                summary.append((preset, p, r["verdict"], r["cells"], len(r["worlds"])))
            for l in sorted({t["label"] for t in trials if t["p_gt"] == p}):
                ts = [t for t in trials if t["label"] == l and t["p_gt"] == p]
                per = [1000.0 * t["planning_s"] / t["nbv_attempts"] for t in ts if t["nbv_attempts"]]
                if per:
                    m, _ = stat(per)
                    timing.append(f"| {preset} | {p:g} | {l} | {stat([t['planning_s'] for t in ts])[0]:.2f} | "
                                  f"{m:.0f} ({max(per):.0f}) |")
    out.append("| preset | P_gt | after 30 | after 60 | after 90 | final | half way at 60 |")
    out.append("|---|---|---|---|---|---|---|")
    for preset, p, v, _, _ in summary:
        cells = ["—" if k not in v else "✔" if v[k] else "✘" for k in ["after 30", "after 60", "after 90", "final", "half way"]]
        out.append(f"| {preset} | {p:g} | " + " | ".join(cells) + " |")
    out.append("")
    out.append(f"| preset, P_gt (worlds) | after 30 | after 60 | after 90 | final | half way to the oracle at 60 |")
    out.append("|---|---|---|---|---|---|")
    for preset, p, _, c, n in summary:
        out.append(f"| {preset}, {p:g} ({n}) | " + " | ".join(c.get(k, "—") for k in
                   ["after 30", "after 60", "after 90", "final", "half way"]) + " |")
    out.append("")
    out.append("| preset | P_gt | method | planning per mission [s] | per NBV attempt [ms], mean (worst mission) |")
    out.append("|---|---|---|---|---|")
    out.extend(timing)
    print("\n".join(out))


if __name__ == "__main__":
    main()
