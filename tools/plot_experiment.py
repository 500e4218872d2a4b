#!/usr/bin/python3
"""Plots of a `canopy report` folder:
fig3_entropy_coverage.png  the paper's Fig. 3: fruit entropy and fruit surface coverage against
                           successful views, mean +- standard deviation bands, one colour per
                           method, solid without segmentation noise (the highest P_gt), dashed with;
fig4_runtime.png           the paper's Fig. 4: stacked bars of mapping, NBV planning, motion
                           planning and control wall time per method (and P_gt), mean over trials;
gain_truth.png             when gain_truth.csv exists: per gain, Spearman's rank correlation with
                           the oracle's truth score and how often its top view is the oracle's
                           top-1 / in its top-5, per method and P_gt whose trials recorded candidates.

Usage: /usr/bin/python3 tools/plot_experiment.py REPORT_DIR   (reads curves.csv and runtime.csv)
"""
import csv
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: E402
except ImportError as e:  # canopy skips the plots with a warning (exit code 3)
    print(f"{os.path.basename(sys.argv[0])}: needs python3-matplotlib ({e})", file=sys.stderr)
    sys.exit(3)

COLOURS = ["tab:red", "tab:blue", "tab:green", "tab:purple", "tab:orange", "tab:brown", "tab:gray"]
FIG4 = [("mapping", "mapping"), ("nbv_planning", "NBV planning"), ("motion_planning", "motion planning"),
        ("control", "control")]


FIELD_CURVES = {
    "fruits_sc80": "fruits above 80 % SC (share)",
    "detection_f1": "fruit detection F1",
    "fruit_voxel_precision": "fruit-voxel precision",
    "sim_time_s": "simulated time [s]",
}


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

    field_path = f"{report}/field_curves.csv"
    field = read(field_path) if os.path.exists(field_path) else []
    metrics = [m for m in FIELD_CURVES if any(r["metric"] == m for r in field)]
    if metrics:
        fig, axes = plt.subplots(1, len(metrics), figsize=(4.2 * len(metrics), 3.8), squeeze=False)
        for ax, metric in zip(axes[0], metrics):
            for lab in labels:
                for p in pgts:
                    rows = [r for r in field if r["label"] == lab and float(r["p_gt"]) == p and r["metric"] == metric]
                    if not rows:
                        continue
                    v = [int(r["view"]) for r in rows]
                    m = [float(r["mean"]) for r in rows]
                    s = [float(r["std"]) for r in rows]
                    ax.plot(v, m, "-" if p == pgts[0] else "--", color=colour[lab], label=f"{lab}, P_gt {p:g}")
                    ax.fill_between(v, [a - b for a, b in zip(m, s)], [a + b for a, b in zip(m, s)],
                                    color=colour[lab], alpha=0.12, lw=0)
            ax.set_xlabel("successful views")
            ax.set_ylabel(FIELD_CURVES[metric])
        axes[0][0].legend(fontsize=7)
        fig.suptitle("The field's metrics after each view, mean ± std over trials "
                     "(solid: no noise, dashed: segmentation noise)", fontsize=10)
        fig.tight_layout()
        fig.savefig(f"{report}/field_curves.png", dpi=110)
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

    try:
        truth = read(f"{report}/gain_truth.csv")
    except FileNotFoundError:
        return
    groups = []
    for r in truth:
        if (r["label"], r["p_gt"]) not in groups:
            groups.append((r["label"], r["p_gt"]))
    scores = [r["score"] for r in truth if (r["label"], r["p_gt"]) == groups[0]]
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    width = 0.8 / len(groups)
    for gi, g in enumerate(groups):
        rows = {r["score"]: r for r in truth if (r["label"], r["p_gt"]) == g}
        xs = [i + gi * width for i in range(len(scores))]
        for ax, key, title in zip(axes, ["spearman", "top1", "top5"],
                                  ["Spearman ρ with the truth (mean over rounds)", "top view = truth's top-1",
                                   "top view in truth's top-5"]):
            ax.bar(xs, [float(rows[s][key]) for s in scores], width, label=f"{g[0]} P_gt {float(g[1]):g}",
                   color=COLOURS[gi % len(COLOURS)])
            ax.set_title(title, fontsize=10)
    for ax in axes:
        ax.set_xticks([i + 0.4 - width / 2 for i in range(len(scores))])
        ax.set_xticklabels(scores, rotation=45, ha="right", fontsize=8)
    axes[0].legend(fontsize=8)
    fig.suptitle("Every gain against the ground truth (oracle) on the candidates of the planning rounds", fontsize=10)
    fig.tight_layout()
    fig.savefig(f"{report}/gain_truth.png", dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    try:
        main(sys.argv[1])
    except OSError as e:  # one line (disk full, unwritable): canopy fails the command
        print(f"plot_experiment: {e.strerror or e}: {e.filename or ''}", file=sys.stderr)
        sys.exit(1)
