#!/usr/bin/env python3
"""Issue 32's goal for a planner, over experiment folders: SC after 30, 60 and 90 successful
views and at the end, at least frontier's and global's, and after 60 views at least half way from
the better of them to the oracle. Means over the world seeds on which every method of the
experiment completed (ok trials), per P_gt; each world's SC after k views is the coverage
recorded with its k-th successful view (its last when it took fewer).

    python3 tools/goal_check.py [--method shape] EXPERIMENT_DIR [...]
"""
import csv
import glob
import os
import statistics
import sys


def main(argv):
    method = "shape"
    args = argv[1:]
    if len(args) >= 2 and args[0] == "--method":
        method, args = args[1], args[2:]
    if not args:
        print(__doc__, file=sys.stderr)
        return 2
    sc = {}  # (pgt, label, world) -> (sc30, sc60, sc90, final, views)
    for exp in args:
        if not os.path.isdir(os.path.join(exp, "trials")):
            print(f"{exp}: not an experiment folder (no trials/)", file=sys.stderr)
            return 2
        for path in glob.glob(os.path.join(exp, "trials", "*", "mission", "views.csv")):
            tid = os.path.basename(os.path.dirname(os.path.dirname(path)))
            if tid.endswith(".partial") or "_world" not in tid:
                continue
            label, rest = tid.split("_pgt", 1)
            pgt, rest = rest.split("_", 1)
            world = rest.split("_world", 1)[-1].split("_", 1)[0]
            by_view = {}
            with open(path, newline="") as f:
                for r in csv.DictReader(f):
                    if r["success"] in ("1", "true"):
                        by_view[int(r["successful_views"])] = float(r["coverage"])
            if not by_view:
                continue
            last = max(by_view)

            def at(k):
                return by_view[max(v for v in by_view if v <= k)] if min(by_view) <= k else 0.0

            sc[(pgt, label, world)] = (at(30), at(60), at(90), by_view[last], last)
    labels = sorted({k[1] for k in sc})
    for pgt in sorted({k[0] for k in sc}, key=lambda p: -float(p)):
        worlds = sorted({k[2] for k in sc if k[0] == pgt})
        complete = [w for w in worlds if all((pgt, l, w) in sc for l in labels)]
        if not complete or method not in labels:
            continue
        print(f"\nP_gt {pgt}: {len(complete)} worlds every method completed ({', '.join(complete)})\n")
        print("| method | SC after 30 | after 60 | after 90 | final | views |")
        print("|---|---|---|---|---|---|")
        mean = {}
        for l in labels:
            cols = list(zip(*[sc[(pgt, l, w)] for w in complete]))
            mean[l] = [statistics.mean(c) for c in cols]
            sd = [statistics.stdev(c) if len(c) > 1 else 0.0 for c in cols]
            name = l + (" (reads the truth)" if l.startswith("oracle") else "")
            print(f"| {name} | " + " | ".join(f"{m:.3f} ± {s:.3f}" for m, s in zip(mean[l][:4], sd[:4])) +
                  f" | {mean[l][4]:.1f} |")
        base = [l for l in ("frontier", "global") if l in mean]
        if not base:
            continue
        checks = []
        for i, name in enumerate(("30", "60", "90", "final")):
            best = max(mean[b][i] for b in base)
            checks.append(f"after {name}: {mean[method][i]:.3f} vs {best:.3f} {'ok' if mean[method][i] >= best else 'NOT met'}")
        if "oracle" in mean:
            best60 = max(mean[b][1] for b in base)
            half = best60 + 0.5 * (mean["oracle"][1] - best60)
            checks.append(f"half way to the oracle after 60: {mean[method][1]:.3f} vs {half:.3f} "
                          f"{'ok' if mean[method][1] >= half else 'NOT met'}")
        print(f"\n{method} against the better of {' and '.join(base)}: " + "; ".join(checks))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
