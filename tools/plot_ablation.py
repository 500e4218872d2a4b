#!/usr/bin/python3
"""Plots of `canopy ablate` (paper Fig. 5 and 6): fruit entropy and surface coverage against
views, mean +- std over trials, one line per gain (with our ray set) or per ray set (with
OSAMCEP); solid without segmentation noise (P_gt = 1), dashed with it.

Usage: /usr/bin/python3 tools/plot_ablation.py OUT_DIR   (reads OUT_DIR/summary.csv)
"""
import csv
import os
import sys
from collections import defaultdict

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: E402
except ImportError as e:  # canopy skips the plots with a warning (exit code 3)
    print(f"{os.path.basename(sys.argv[0])}: needs python3-matplotlib ({e})", file=sys.stderr)
    sys.exit(3)


def load(path):
    rows = defaultdict(list)
    with open(path) as f:
        for r in csv.DictReader(f):
            rows[(r["gain"], r["rays"], float(r["p_gt"]))].append(r)
    return rows


def plot(rows, keys, label_of, title, out):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    colors = {}
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for key in sorted(keys, key=lambda k: (label_of(k), -k[2])):
        lab = label_of(key)
        if lab not in colors:
            colors[lab] = cycle[len(colors) % len(cycle)]
        rs = sorted(rows[key], key=lambda r: int(r["view"]))
        v = [int(r["view"]) for r in rs]
        style = "-" if key[2] >= 1.0 else "--"
        for ax, name in zip(axes, ["entropy", "coverage"]):
            m = [float(r[name + "_mean"]) for r in rs]
            s = [float(r[name + "_std"]) for r in rs]
            ax.plot(v, m, style, color=colors[lab], label=f"{lab} (P_gt {key[2]:g})")
            ax.fill_between(v, [a - b for a, b in zip(m, s)], [a + b for a, b in zip(m, s)], color=colors[lab],
                            alpha=0.12)
    axes[0].set_ylabel("fruit entropy per plant [nats]")
    axes[1].set_ylabel("fruit surface coverage")
    axes[1].axhline(0.8, color="grey", lw=0.6)
    for ax in axes:
        ax.set_xlabel("views per plant")
        ax.grid(alpha=0.3)
    axes[1].legend(fontsize=7, ncol=2)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def main():
    out = sys.argv[1]
    rows = load(out + "/summary.csv")
    if not rows:
        print("plot_ablation: summary.csv is empty", file=sys.stderr)
        return 1
    rays_main = "ours" if any(k[1] == "ours" for k in rows) else sorted(rows)[0][1]
    # OSAMCEP may run in several variants ("osamcep-per_voxel", ...): the ray-set plot shows each.
    osamcep = [k for k in rows if k[0].startswith("osamcep")]
    gain_main = "osamcep" if osamcep else sorted(rows)[0][0]
    gain_keys = [k for k in rows if k[1] == rays_main]
    ray_keys = osamcep if osamcep else [k for k in rows if k[0] == gain_main]
    plot(rows, gain_keys, lambda k: k[0], f"Information gain metrics (rays: {rays_main})", out + "/gains.png")
    plot(rows, ray_keys, lambda k: k[1] if k[0] == gain_main else f"{k[1]} ({k[0]})", f"Ray sets ({gain_main})",
         out + "/rays.png")
    print(f"plot_ablation: wrote {out}/gains.png and {out}/rays.png")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except BrokenPipeError:  # its last line, to canopy's output piped into `head`: the plots are drawn
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        sys.exit(0)
    except OSError as e:  # one line (disk full, unwritable): canopy fails the command
        print(f"plot_ablation: {e.strerror or e}: {e.filename or ''}", file=sys.stderr)
        sys.exit(1)
