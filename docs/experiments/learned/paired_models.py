#!/usr/bin/env python3
"""Two models of one planner in closed loop on the same worlds, paired (docs/learned.md).

Reads per-trial figures (goal_table.py --csv) of a new and a base model, preset by preset
(PRESET=CSV, or PRESET=CSV:LABEL for the trials of one label of a file holding several), and
prints, per preset and P_gt, the new minus the base after 30, 60 and 90 views and at the end: SC
points, mean ± paired standard error over the worlds both ran (worlds where the new is ahead),
then the mean over every cell. A (P_gt, world) in one set only is left out and counted.

  python3 docs/experiments/learned/paired_models.py \\
      --new default=docs/experiments/learned/tuning_per_noise_default_sc.csv \\
            dense=docs/experiments/learned/tuning_per_noise_dense_sc.csv \\
      --base default=docs/experiments/learned/tuning_tree_default_sc.csv \\
             dense=docs/experiments/learned/tuning_tree_dense_sc.csv
"""
import argparse
import csv
import math
import statistics
import sys

COLUMNS = ["sc_after_30", "sc_after_60", "sc_after_90", "sc_final"]


def fail(msg):
    print(f"paired_models: {msg}", file=sys.stderr)
    sys.exit(2)


def read(path, label=None):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    out = {}
    if label is not None:
        rows = [r for r in rows if r["label"] == label]
        if not rows:
            fail(f"{path}: no trial of label {label}")
    for r in rows:
        key = (float(r["p_gt"]), int(r["world_seed"]))
        if key in out:
            fail(f"{path}: P_gt {key[0]:g}, world {key[1]} given twice (name a label: PRESET=CSV:LABEL)")
        out[key] = [float(r[c]) for c in COLUMNS]
    return out


def sources(specs, what):
    by = {}
    for spec in specs:
        preset, _, path = spec.partition("=")
        if not path:
            fail(f"{what} '{spec}': give preset=file or preset=file:label")
        path, _, label = path.partition(":")
        by.setdefault(preset, {}).update(read(path, label or None))
    return by


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--new", nargs="+", required=True, metavar="PRESET=CSV")
    ap.add_argument("--base", nargs="+", required=True, metavar="PRESET=CSV")
    a = ap.parse_args()
    new, base = sources(a.new, "--new"), sources(a.base, "--base")
    print("| preset, P_gt (worlds) | after 30 | after 60 | after 90 | final |")
    print("|---|---|---|---|---|")
    means = []
    for preset in new:
        if preset not in base:
            fail(f"no --base figures of preset {preset}")
        a_, b_ = new[preset], base[preset]
        for p in sorted({k[0] for k in a_}, reverse=True):
            keys = sorted(k for k in a_ if k[0] == p and k in b_)
            unpaired = sum(1 for k in list(a_) + list(b_) if k[0] == p and not (k in a_ and k in b_))
            if len(keys) < 2:
                print(f"| {preset}, {p:g} | fewer than two paired worlds |  |  |  |")
                continue
            cells = []
            for j in range(len(COLUMNS)):
                d = [100.0 * (a_[k][j] - b_[k][j]) for k in keys]
                m = statistics.mean(d)
                se = statistics.stdev(d) / math.sqrt(len(d))
                means.append(m)
                cells.append(f"{m:+.1f} ± {se:.1f} ({sum(x > 0 for x in d)})".replace("-", "−"))
            extra = f", {unpaired} unpaired left out" if unpaired else ""
            print(f"| {preset}, {p:g} ({len(keys)}{extra}) | " + " | ".join(cells) + " |")
    if means:
        print(f"\nMean over the {len(means)} cells: {statistics.mean(means):+.2f} points".replace("-", "−"))


if __name__ == "__main__":
    main()
