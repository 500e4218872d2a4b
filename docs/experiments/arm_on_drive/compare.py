#!/usr/bin/env python3
"""mission.stops.arm_on_drive: clear against hold, trial by trial (docs/experiments/arm_on_drive).

Each argument is PRESET=CLEAR_RUN:HOLD_RUN, two `canopy experiment` --out folders of the same
trials (the same methods, worlds, P_gt and seeds), the first run with `clear` (or another setting,
named by --label), the second with `hold`. Prints, per preset, P_gt and method: the missions in which the arm went home at least
once, the moves home, the stops lost (no successful view) in each run, fruit SC after the 60th
successful view and at the end in each run with the paired difference (SC points, mean ± paired
standard error over the worlds), then per preset the failed attempts, plan_timeout among them, the
simulated time per mission and whether every mission without a move home gave the same views.csv.
--csv FILE also writes one row per trial.

  python3 docs/experiments/arm_on_drive/compare.py default=runs/learned_eval:runs/hold_eval \\
      dense=runs/learned_eval_dense:runs/hold_eval_dense --csv trials.csv

(Fig. 3's experiment files run with the default, `clear` since 7 December 2026; hold_eval*.yaml
beside this script are the same missions with `hold`.)
"""
import argparse
import csv
import json
import math
import pathlib
import sys

METHODS = ["learned", "shape", "frontier", "global", "reveal", "ours", "predefined", "oracle"]


def figures(trial):
    """The figures of one finished trial folder."""
    summary = json.loads((trial / "mission" / "summary.json").read_text())
    sc60 = 0.0
    with open(trial / "mission" / "views.csv", newline="") as f:
        for row in csv.DictReader(f):
            if int(row["successful_views"]) <= 60:
                sc60 = float(row["coverage"])
    stops = summary["stops"]
    codes = [s.get("arm_on_drive", "held") for s in stops]
    failures = sum(sum(s["failures"].values()) for s in stops)
    timeouts = sum(s["failures"].get("plan_timeout", 0) for s in stops)
    return {
        "sc": summary["final"]["fruit_coverage"],
        "sc60": sc60,
        "lost": sum(1 for s in stops if s["initial_successful"] + s["nbv_successful"] == 0),
        "home": codes.count("home"),
        "blocked": codes.count("blocked"),
        "failures": failures,
        "timeouts": timeouts,
        "sim": summary["simulated_time_s"],
        "views_csv": (trial / "mission" / "views.csv").read_bytes(),
    }


def paired(xs):
    n = len(xs)
    m = sum(xs) / n
    se = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1) / n) if n > 1 else 0.0
    return m, se


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="PRESET=CLEAR_RUN:HOLD_RUN")
    ap.add_argument("--csv", help="one row per trial")
    ap.add_argument("--label", default="clear", help="the first run's setting, in the table's header")
    a = ap.parse_args()
    rows = []
    for spec in a.runs:
        if "=" not in spec or ":" not in spec.split("=", 1)[1]:
            sys.exit(f"compare.py: '{spec}' is not PRESET=CLEAR_RUN:HOLD_RUN")
        preset, pair = spec.split("=", 1)
        clear_run, hold_run = (pathlib.Path(p) for p in pair.split(":", 1))
        trials = sorted(p for p in (clear_run / "trials").iterdir() if (p / "trial.json").is_file())
        if not trials:
            sys.exit(f"compare.py: no finished trial in {clear_run / 'trials'}")
        by = {}
        same = changed_without_home = 0
        totals = {"clear": [0, 0, 0.0], "hold": [0, 0, 0.0]}
        for t in trials:
            meta = json.loads((t / "trial.json").read_text())["trial"]
            other = hold_run / "trials" / t.name
            if not (other / "trial.json").is_file():
                sys.exit(f"compare.py: {other} is missing (the two runs must hold the same trials)")
            c, h = figures(t), figures(other)
            if c["home"] + c["blocked"] == 0:
                same += c["views_csv"] == h["views_csv"]
                changed_without_home += c["views_csv"] != h["views_csv"]
            for tag, f in (("clear", c), ("hold", h)):
                totals[tag][0] += f["failures"]
                totals[tag][1] += f["timeouts"]
                totals[tag][2] += f["sim"]
            by.setdefault((meta["p_gt"], meta["label"]), []).append((c, h))
            rows.append([preset, t.name, meta["label"], meta["p_gt"], c["home"], c["blocked"], h["lost"], c["lost"],
                         f"{h['sc60']:.6f}", f"{c['sc60']:.6f}", f"{h['sc']:.6f}", f"{c['sc']:.6f}"])
        print(f"## {preset}\n")
        c = a.label
        print(f"| P_gt | method | missions with a move home | moves home | stops lost, hold → {c} | "
              f"SC after 60 views, hold → {c} (paired, points) | final SC, hold → {c} (paired, points) |")
        print("|---|---|---|---|---|---|---|")
        for p_gt in sorted({k[0] for k in by}, reverse=True):
            for label in METHODS + sorted({k[1] for k in by} - set(METHODS)):
                r = by.get((p_gt, label))
                if not r:
                    continue
                n = len(r)
                moved = sum(1 for c, _ in r if c["home"] + c["blocked"] > 0)
                d60 = paired([100 * (c["sc60"] - h["sc60"]) for c, h in r])
                dend = paired([100 * (c["sc"] - h["sc"]) for c, h in r])
                print(f"| {p_gt} | {label} | {moved} of {n} | {sum(c['home'] for c, _ in r)} | "
                      f"{sum(h['lost'] for _, h in r)} → {sum(c['lost'] for c, _ in r)} | "
                      f"{sum(h['sc60'] for _, h in r) / n:.3f} → {sum(c['sc60'] for c, _ in r) / n:.3f} "
                      f"({d60[0]:+.1f} ± {d60[1]:.1f}) | "
                      f"{sum(h['sc'] for _, h in r) / n:.3f} → {sum(c['sc'] for c, _ in r) / n:.3f} "
                      f"({dend[0]:+.1f} ± {dend[1]:.1f}) |")
        n = len(trials)
        blocked = sum(c["blocked"] for v in by.values() for c, _ in v)
        print(f"\n{n} missions; failed attempts hold {totals['hold'][0]} → {a.label} {totals['clear'][0]} "
              f"(plan_timeout {totals['hold'][1]} → {totals['clear'][1]}); simulated time per mission "
              f"{totals['hold'][2] / n:.1f} → {totals['clear'][2] / n:.1f} s; drives with the arm in the way "
              f"and no move home: {blocked}; missions without a move home: {same + changed_without_home}, "
              f"views.csv the same in {same}\n")
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["preset", "trial", "method", "p_gt", "moves_home", "blocked", "stops_lost_hold",
                        "stops_lost_clear", "sc60_hold", "sc60_clear", "sc_final_hold", "sc_final_clear"])
            w.writerows(rows)


if __name__ == "__main__":
    main()
