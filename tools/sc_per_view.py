#!/usr/bin/python3
"""SC added per successful view, by phase and method, over the trials of experiment folders.

For every ok trial (trials/<id>/mission/views.csv): the fruit surface coverage (headline rule)
added by the successful views of each phase (initial scan; nbv / predefined / replacement: the
views after it), divided by their number; then mean ± sample std over the trials of each
(method label, P_gt), also the SC after 60 and 90 successful views and at the end.

Usage: /usr/bin/python3 tools/sc_per_view.py [--worlds 1001,1002] EXPERIMENT_DIR [EXPERIMENT_DIR ...] > table.md
(--worlds: only the trials of these world seeds, e.g. the worlds every method completed)
"""
import csv
import glob
import os
import statistics
import sys


def trial_rows(folder):
    for d in sorted(glob.glob(os.path.join(folder, "trials", "*"))):
        views = os.path.join(d, "mission", "views.csv")
        if d.endswith(".partial") or not os.path.exists(views):
            continue
        with open(views) as f:
            yield os.path.basename(d), list(csv.DictReader(f))


def stats(v):
    if not v:
        return "n/a"
    if len(v) == 1:
        return f"{v[0]:.4g} (n=1)"
    return f"{statistics.mean(v):.4g} ± {statistics.stdev(v):.2g} (n={len(v)})"


def main(folders, worlds=None):
    groups = {}
    for folder in folders:
        for tid, rows in trial_rows(folder):
            if worlds is not None and not any(f"_world{w}_" in tid for w in worlds):
                continue
            label, pgt = tid.split("_pgt")[0], tid.split("_pgt")[1].split("_")[0]
            g = groups.setdefault((label, pgt), {"init": [], "later": [], "sc60": [], "sc90": [], "final": [], "views": []})
            prev, added = 0.0, {"init": [0.0, 0], "later": [0.0, 0]}
            curve = []
            for r in rows:
                if r["success"] != "1":
                    continue
                sc = float(r["coverage"])
                key = "init" if r["phase"] == "initial" else "later"
                added[key][0] += sc - prev
                added[key][1] += 1
                prev = sc
                curve.append(sc)
            for key in ("init", "later"):
                if added[key][1]:
                    g[key].append(1e3 * added[key][0] / added[key][1])
            if len(curve) >= 60:
                g["sc60"].append(curve[59])
            if len(curve) >= 90:
                g["sc90"].append(curve[89])
            g["final"].append(curve[-1] if curve else 0.0)
            g["views"].append(len(curve))
    print("| method | P_gt | successful views | SC after 60 | SC after 90 | final SC "
          "| SC added per initial-scan view (1e-3) | SC added per later view (1e-3) |")
    print("|---|---|---|---|---|---|---|---|")
    for (label, pgt), g in sorted(groups.items(), key=lambda kv: (-float(kv[0][1]), kv[0][0])):
        print(f"| {label} | {pgt} | {stats(g['views'])} | {stats(g['sc60'])} | {stats(g['sc90'])} | "
              f"{stats(g['final'])} | {stats(g['init'])} | {stats(g['later'])} |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    args = sys.argv[1:]
    worlds = None
    if args[0] == "--worlds":
        worlds, args = args[1].split(","), args[2:]
    main(args, worlds)
