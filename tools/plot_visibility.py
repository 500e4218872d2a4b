#!/usr/bin/python3
"""Plot of `canopy visibility`: fruit detectability per camera position and of the best
combination of k positions, per world seed (and pooled), beside Hemming et al.'s (2014)
commercial-crop figures. Usage: plot_visibility.py FOLDER (reads visibility.csv and
combinations.csv, writes visibility.png)."""

import csv
import json
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    folder = sys.argv[1]
    rows = read(os.path.join(folder, "visibility.csv"))
    combos = read(os.path.join(folder, "combinations.csv"))
    if not rows:
        print("plot_visibility: visibility.csv is empty", file=sys.stderr)
        return 1
    positions = []
    per_seed = defaultdict(list)
    for r in rows:
        if r["position"] not in positions:
            positions.append(r["position"])
        per_seed[r["seed"]].append(100.0 * float(r["detectability"]))
    best = defaultdict(list)
    for r in combos:
        best[r["seed"]].append((int(r["k"]), 100.0 * float(r["detectability"])))
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 5), gridspec_kw={"width_ratios": [2.2, 1]})
    seeds = list(per_seed)
    width = 0.8 / len(seeds)
    for i, s in enumerate(seeds):
        xs = [p + (i - (len(seeds) - 1) / 2) * width for p in range(len(positions))]
        a.bar(xs, per_seed[s], width, label=("seed " + s) if s != "all" else "all seeds",
              color="black" if s == "all" else None)
    a.axhline(69, color="red", ls="--", lw=1, label="Hemming et al.: best single position 69 %")
    a.set_xticks(range(len(positions)))
    a.set_xticklabels(positions, rotation=60, ha="right", fontsize=8)
    a.set_ylabel("fruit detectability [%]")
    a.set_ylim(0, 100)
    a.set_title("per camera position")
    a.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.3), ncol=5)
    for s in seeds:
        ks = [k for k, _ in best[s]]
        b.plot(ks, [d for _, d in best[s]], marker="o", color="black" if s == "all" else None,
               lw=2 if s == "all" else 1, label=("seed " + s) if s != "all" else "all seeds (one combination)")
    b.plot([1, 5], [69, 90], "r*", ms=12, label="Hemming et al. (k = 1, 5)")
    b.set_xlabel("positions combined (k, best combination)")
    b.set_ylabel("fruit detectability [%]")
    b.set_ylim(0, 100)
    b.set_xticks([1, 2, 3, 4, 5])
    b.set_title("best combination of k positions")
    b.legend(fontsize=7, loc="lower right")
    with open(os.path.join(folder, "visibility.json")) as f:
        world = json.load(f).get("world", "")
    fig.suptitle("Fruit detectability (at most 50 %% of the camera-facing surface hidden), world '%s'" % world)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "visibility.png"), dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
