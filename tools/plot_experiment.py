#!/usr/bin/python3
"""Plots of a `canopy report` folder:
fig3_entropy_coverage.png  the paper's Fig. 3: fruit entropy and fruit surface coverage against
                           successful views, mean +- standard deviation bands, one colour per
                           method, solid without segmentation noise (the highest P_gt), dashed with;
fig4_runtime.png           the paper's Fig. 4: stacked bars of mapping, NBV planning, motion
                           planning and control wall time per method (and P_gt), mean over trials.

Usage: /usr/bin/python3 tools/plot_experiment.py REPORT_DIR   (reads curves.csv and runtime.csv)
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = ["tab:red", "tab:blue", "tab:green", "tab:purple", "tab:orange", "tab:brown", "tab:gray"]
FIG4 = [("mapping", "mapping"), ("nbv_planning", "NBV planning"), ("motion_planning", "motion planning"),
        ("control", "control")]


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main(report):
    curves = read(f"{report}/curves.csv")
    runtime = read(f"{report}/runtime.csv")
    labels = []
    for r in runtime:
        if r["label"] not in labels:
            labels.append(r["label"])
    colour = {lab: COLOURS[i % len(COLOURS)] for i, lab in enumerate(labels)}
    pgts = sorted({float(r["p_gt"]) for r in runtime}, reverse=True)

    fig, (ax_h, ax_sc) = plt.subplots(1, 2, figsize=(11, 4.2))
    for lab in labels:
        for p in pgts:
            rows = [r for r in curves if r["label"] == lab and float(r["p_gt"]) == p]
            if not rows:
                continue
            v = [int(r["view"]) for r in rows]
            style = "-" if p == pgts[0] else "--"
            for ax, key in ((ax_h, "entropy"), (ax_sc, "sc")):
                m = [float(r[f"{key}_mean"]) for r in rows]
                s = [float(r[f"{key}_std"]) for r in rows]
                ax.plot(v, m, style, color=colour[lab], label=f"{lab}, P_gt {p:g}")
                ax.fill_between(v, [a - b for a, b in zip(m, s)], [a + b for a, b in zip(m, s)],
                                color=colour[lab], alpha=0.12, lw=0)
    ax_h.set_xlabel("successful views")
    ax_h.set_ylabel("total fruit entropy [nats]")
    ax_sc.set_xlabel("successful views")
    ax_sc.set_ylabel("fruit surface coverage")
    ax_sc.set_ylim(0, 1)
    ax_sc.legend(fontsize=8, loc="lower right")
    n = max((int(r["trials"]) for r in runtime), default=0)
    fig.suptitle(f"Entropy and surface coverage, mean ± std over up to {n} trials "
                 "(solid: no noise, dashed: segmentation noise)", fontsize=10)
    fig.tight_layout()
    fig.savefig(f"{report}/fig3_entropy_coverage.png", dpi=120)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(1.6 + 1.3 * len(runtime), 4.2))
    names = [f"{r['label']}\nP_gt {float(r['p_gt']):g}\n(n={r['trials']})" for r in runtime]
    bottom = [0.0] * len(runtime)
    for key, title in FIG4:
        vals = [float(r[f"{key}_s_mean"]) for r in runtime]
        ax.bar(names, vals, bottom=bottom, label=title)
        bottom = [a + b for a, b in zip(bottom, vals)]
    ax.set_ylabel("wall time per mission [s]")
    ax.set_title("Run time split (mean over trials)", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{report}/fig4_runtime.png", dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
