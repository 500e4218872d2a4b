#!/usr/bin/env python3
"""Per-fruit shape completion against the voxel-only figures, over experiment folders.

Reads every trial's mission/fruit_shapes.csv (one row per matched fruit, docs/shape.md) and
prints a Markdown table per method label and P_gt: matched fruits, the mean centre error of the
voxels' centroid and of the fitted shape, and the mean relative volume errors of the voxel
volume, the moment ellipsoid and the fitted shape (medians in brackets).

    python3 docs/experiments/shape/fruit_shapes_summary.py runs/shape_fig3 [more experiment folders]
"""
import csv
import glob
import math
import os
import statistics
import sys


def trial_key(trial_dir):
    tid = os.path.basename(trial_dir)
    label, rest = tid.split("_pgt", 1)
    return label, rest.split("_", 1)[0]


def main(argv):
    if len(argv) < 2:
        print("usage: fruit_shapes_summary.py EXPERIMENT_DIR [...]", file=sys.stderr)
        return 2
    rows = {}
    for exp in argv[1:]:
        if not os.path.isdir(os.path.join(exp, "trials")):
            print(f"{exp}: not an experiment folder (no trials/)", file=sys.stderr)
            return 2
        for path in sorted(glob.glob(os.path.join(exp, "trials", "*", "mission", "fruit_shapes.csv"))):
            trial = os.path.dirname(os.path.dirname(path))
            if trial.endswith(".partial"):
                continue
            with open(path, newline="") as f:
                rows.setdefault(trial_key(trial), []).extend(csv.DictReader(f))

    def col(rs, name):
        return [float(r[name]) for r in rs if r[name] not in ("", None) and math.isfinite(float(r[name]))]

    def fmt(v, scale=1.0, digits=1):
        if not v:
            return "–"
        return f"{statistics.mean(v) * scale:.{digits}f} ({statistics.median(v) * scale:.{digits}f})"

    print("| method | P_gt | fruits | fitted | centre error, centroid [mm] | centre error, shape [mm] | "
          "volume error, voxels [%] | volume error, moment ellipsoid [%] | volume error, shape [%] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for (label, pgt), rs in sorted(rows.items(), key=lambda kv: (-float(kv[0][1]), kv[0][0])):
        fitted = [r for r in rs if r["shape_ok"] == "1"]
        print(f"| {label} | {pgt} | {len(rs)} | {len(fitted)} | {fmt(col(rs, 'centroid_error_m'), 1e3)} | "
              f"{fmt(col(fitted, 'shape_centre_error_m'), 1e3)} | {fmt(col(rs, 'voxel_volume_error'), 100, 0)} | "
              f"{fmt(col(rs, 'ellipsoid_volume_error'), 100, 0)} | {fmt(col(fitted, 'shape_volume_error'), 100, 0)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
