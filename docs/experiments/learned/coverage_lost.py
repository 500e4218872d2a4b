#!/usr/bin/env python3
"""What segmentation noise takes back: fruit SC gained and lost view by view (issue 47).

For each experiment folder given (a `canopy experiment` --out folder), each P_gt and method: over
the first N successful views of each trial (default 60), the SC gained by the views that raised it,
the SC lost by the views that lowered it (label noise can turn fruit voxels seen before into leaf
or background), and how many views lowered it; means over the trials. SC after N views is the gain
minus the loss. With --chosen METHOD, also the chosen candidates of that method's audited rounds
(`candidates.csv`, the view each round planned first) split by whether the view after them lost
SC, with the mean of a few of their features.

  python3 docs/experiments/learned/coverage_lost.py runs/learned_eval runs/learned_eval_dense
  python3 docs/experiments/learned/coverage_lost.py runs/learned_eval --chosen learned --p-gt 0.7
"""
import argparse
import collections
import csv
import json
import pathlib
import statistics
import sys


def trials(folder):
    for t in sorted(pathlib.Path(folder).glob("trials/*/trial.json")):
        info = json.loads(t.read_text())
        if info.get("status") != "ok":
            continue
        views = t.parent / "mission" / "views.csv"
        if views.exists():
            yield info["trial"], t.parent / "mission"


def coverage(mission):
    rows = [r for r in csv.DictReader(open(mission / "views.csv")) if r["success"] == "1"]
    return [0.0] + [float(r["coverage"]) for r in rows]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folders", nargs="+")
    ap.add_argument("--views", type=int, default=60, help="successful views counted (default 60)")
    ap.add_argument("--chosen", help="a method whose audited chosen candidates to split by the loss")
    ap.add_argument("--p-gt", type=float, help="with --chosen: only this P_gt")
    a = ap.parse_args()
    for folder in a.folders:
        if not (pathlib.Path(folder) / "trials").is_dir():
            sys.exit(f"coverage_lost.py: {folder} is not a canopy experiment folder (no trials/)")
        acc = collections.defaultdict(list)
        chosen = []
        for trial, mission in trials(folder):
            cov = coverage(mission)
            n = min(a.views, len(cov) - 1)
            steps = [cov[i] - cov[i - 1] for i in range(1, n + 1)]
            acc[(trial["p_gt"], trial["label"])].append(
                (sum(d for d in steps if d > 0), -sum(d for d in steps if d < 0), sum(d < 0 for d in steps), cov[n]))
            if a.chosen and trial["label"] == a.chosen and (a.p_gt is None or trial["p_gt"] == a.p_gt):
                audit = mission / "candidates.csv"
                if audit.exists():
                    for r in csv.DictReader(open(audit)):
                        before = int(r["views_before"])
                        if r["chosen"] == "1" and before + 1 < len(cov):
                            chosen.append((cov[before + 1] - cov[before], r))
        print(f"{folder}: the first {a.views} successful views, means over the trials")
        print("| P_gt | method | trials | SC after them | gained | lost | views that lost SC |")
        print("|---|---|---|---|---|---|---|")
        for (p, label), v in sorted(acc.items(), key=lambda kv: (-kv[0][0], kv[0][1])):
            m = lambda i: statistics.mean(x[i] for x in v)
            print(f"| {p:g} | {label} | {len(v)} | {m(3):.3f} | {m(0):.3f} | {m(1):.3f} | {m(2):.1f} |")
        if a.chosen:
            lost = [(d, r) for d, r in chosen if d < 0]
            kept = [(d, r) for d, r in chosen if d >= 0]
            print(f"\n{a.chosen}'s chosen candidates: {len(chosen)}, the view after {len(lost)} of them lost SC")
            for f in ["f:fruit_logodds_mean", "f:fruit_logodds_min", "f:fruit_seen", "f:fruit_voxels"]:
                if not chosen or f not in chosen[0][1]:
                    continue
                x = [float(r[f]) for _, r in lost]
                y = [-d for d, _ in lost]
                corr = statistics.correlation(x, y) if len(x) > 2 else float("nan")
                print(f"  {f}: mean {statistics.mean(x):.3f} where SC was lost, {statistics.mean(float(r[f]) for _, r in kept):.3f} "
                      f"elsewhere; its correlation with the loss's size {corr:+.2f}")


if __name__ == "__main__":
    main()
