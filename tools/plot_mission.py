#!/usr/bin/python3
"""Plots of one `canopy mission` run: sc_entropy.png (fruit surface coverage and fruit entropy
against successful views, stops marked) and runtime.png (the paper's Fig. 4 bars for this run:
wall time of mapping, NBV planning, motion planning and control).

Usage: /usr/bin/python3 tools/plot_mission.py RUN_DIR   (reads views.csv and summary.json)
"""
import csv
import os
import json
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: E402
except ImportError as e:  # canopy skips the plots with a warning (exit code 3)
    print(f"{os.path.basename(sys.argv[0])}: needs python3-matplotlib ({e})", file=sys.stderr)
    sys.exit(3)

# The paper's Fig. 4 categories and the canopy phases they hold.
CATEGORIES = [
    ("mapping", ["mapping"]),
    ("NBV planning", ["clustering", "candidates", "filtering", "scoring", "nbv_planning"]),
    ("motion planning", ["motion_planning"]),
    ("control", ["control"]),
    ("rendering", ["rendering"]),
    ("evaluation", ["evaluation"]),
]


def main(run):
    with open(f"{run}/views.csv") as f:
        views = [r for r in csv.DictReader(f) if r["success"] == "1"]
    with open(f"{run}/summary.json") as f:
        summary = json.load(f)
    method = summary.get("method", {}).get("name", "?")

    fig, ax1 = plt.subplots(figsize=(8, 4.2))
    n = [int(r["successful_views"]) for r in views]
    ax1.plot(n, [float(r["coverage"]) for r in views], color="tab:red", label="fruit surface coverage")
    ax1.set_xlabel("successful views")
    ax1.set_ylabel("fruit surface coverage", color="tab:red")
    ax1.set_ylim(0, 1)
    ax2 = ax1.twinx()
    ax2.plot(n, [float(r["entropy"]) for r in views], color="tab:blue", label="fruit entropy")
    ax2.set_ylabel("fruit entropy [nats]", color="tab:blue")
    for i in range(1, len(views)):
        if views[i]["stop"] != views[i - 1]["stop"]:
            ax1.axvline(n[i] - 0.5, color="0.8", lw=0.8)
    ax1.set_title(f"canopy mission ({method}, P_gt {summary.get('p_gt')}, seed {summary.get('seed')})")
    fig.tight_layout()
    fig.savefig(f"{run}/sc_entropy.png", dpi=120)
    plt.close(fig)

    phases = summary.get("wall_time_by_phase_s", {})
    labels = [c for c, _ in CATEGORIES]
    values = [sum(phases.get(p, 0.0) for p in ps) for _, ps in CATEGORIES]
    fig, ax = plt.subplots(figsize=(6, 4))
    bottom = 0.0
    for lab, v in zip(labels, values):
        ax.bar([method], [v], bottom=[bottom], label=f"{lab} ({v:.1f} s)")
        bottom += v
    ax.set_ylabel("wall time [s]")
    ax.set_title(f"run time split ({summary.get('simulated_time_s', 0):.0f} s simulated)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{run}/runtime.png", dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    try:
        main(sys.argv[1])
    except OSError as e:  # one line (disk full, unwritable): canopy fails the command
        print(f"plot_mission: {e.strerror or e}: {e.filename or ''}", file=sys.stderr)
        sys.exit(1)
