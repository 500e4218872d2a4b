#!/usr/bin/env python3
"""Every method's final SC in a new Fig. 3 run against the old Fig. 3's (issue 49, point 3).

The new run is an experiment folder (per-trial data); the old one is what its page committed,
runtime.csv's final_sc_mean / final_sc_std / trials per method and P_gt (the old per-trial SC was
not committed, so the difference's standard error is the unpaired one, sqrt(s_new^2/n_new +
s_old^2/n_old); a mean equal to the old one to 1e-6, the old CSV's precision, is taken for the same
trials, a paired difference of 0). --old-row adds a method the old page
lacks (label,p_gt,mean,std,n). Prints one markdown table: new, old, new - old in SC points ± its
standard error, and whether the change is within one and within two standard errors.

  git show fdb9fd2:docs/experiments/fig3/runtime.csv > /tmp/fig3_old.csv
  python3 docs/experiments/learned/against_old_fig3.py default=runs/learned_eval:/tmp/fig3_old.csv
  python3 docs/experiments/learned/against_old_fig3.py dense=docs/experiments/fig3_dense/trials_sc.csv,runs/more:/tmp/old.csv
"""
import argparse
import csv
import math
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import goal_table  # noqa: E402  (its readers of experiment folders and per-trial files)


def new_finals(sources):
    """{(label, p_gt): [final SC per world]} of the ok trials of experiment folders or per-trial
    .csv files (goal_table.py --csv), joined; a (label, p_gt, world) given twice is refused."""
    out = {}
    seen = set()
    for source in sources.split(","):
        for t in goal_table.load(source):
            key = (t["label"], t["p_gt"], t["world"])
            if key in seen:
                sys.exit(f"against_old_fig3: {key} is in two sources")
            seen.add(key)
            out.setdefault((t["label"], t["p_gt"]), []).append(t["sc"]["final"])
    return out


def old_finals(path, extra):
    """{(label, p_gt): (mean, std, n)} from an old page's runtime.csv and the --old-row lines."""
    out = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            out[(row["label"], float(row["p_gt"]))] = (float(row["final_sc_mean"]), float(row["final_sc_std"]),
                                                       int(row["trials"]))
    for e in extra:
        label, p, m, s, n = e.split(",")
        out[(label, float(p))] = (float(m), float(s), int(n))
    return out


def stat(xs):
    m = sum(xs) / len(xs)
    s = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1)) if len(xs) > 1 else 0.0
    return m, s


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("pairs", nargs="+", help="preset=new experiment folders or per-trial .csv files (comma-separated):old runtime.csv")
    ap.add_argument("--old-row", action="append", default=[], help="preset:label,p_gt,mean,std,n (a method the old page lacks)")
    a = ap.parse_args()
    print("| preset | P_gt | method | new final SC (n) | old final SC (n) | new − old, SC points ± SE | within 1 SE / 2 SE |")
    print("|---|---|---|---|---|---|---|")
    for spec in a.pairs:
        preset, _, rest = spec.partition("=")
        folder, _, old_path = rest.partition(":")
        if not old_path:
            sys.exit(f"against_old_fig3: '{spec}': give preset=folder:old_runtime.csv")
        new = new_finals(folder)
        old = old_finals(old_path, [r.partition(":")[2] for r in a.old_row if r.partition(":")[0] == preset])
        for (label, p) in sorted(new, key=lambda k: (-k[1], k[0])):
            xs = new[(label, p)]
            m, s = stat(xs)
            if (label, p) not in old:
                print(f"| {preset} | {p:g} | {label} | {m:.3f} ± {s:.3f} ({len(xs)}) | — | new method | — |")
                continue
            om, osd, on = old[(label, p)]
            d = 100.0 * (m - om)
            se = 100.0 * math.sqrt(s * s / len(xs) + osd * osd / on)
            verdict = ("yes / yes" if abs(d) <= se else "no / yes" if abs(d) <= 2 * se else "no / no")
            change = f"{d:+.1f} ± {se:.1f}".replace("-", "−")
            if abs(m - om) < 1e-6:  # the old CSV's 6 digits: the same trials, paired difference 0
                change, verdict = "0 (the same mean to 1e-6)", "yes / yes"
            print(f"| {preset} | {p:g} | {label} | {m:.3f} ± {s:.3f} ({len(xs)}) | {om:.3f} ± {osd:.3f} ({on}) | "
                  f"{change} | {verdict} |")


if __name__ == "__main__":
    main()
