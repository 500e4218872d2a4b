#!/usr/bin/python3
"""Attempts, start-state repairs and stop ends of the trials of experiment folders (issue 32).

For every ok trial (trials/<id>/mission/summary.json): attempts, successes, the attempts lost to
start_in_collision per stop, start repairs, and why each stop ended; per method and in all.
The checks: no stop loses more than one attempt to start_in_collision, and at least 95 % of all
attempts succeed. Also the success rate of the attempts that got past the view's own refusals
(no IK, every goal in collision with the map: refused before the arm moved), which are the
method's choice of views rather than the controller's; and the scripted views a planner refused
when planning (summary.json "refused": predefined scanning's goal test), which are not attempts.

Usage: /usr/bin/python3 docs/experiments/loop/attempts.py EXPERIMENT_DIR [EXPERIMENT_DIR ...] > attempts.md
"""
import glob
import json
import os
import sys
from collections import Counter


def trials(folder):
    for d in sorted(glob.glob(os.path.join(folder, "trials", "*"))):
        summary = os.path.join(d, "mission", "summary.json")
        if d.endswith(".partial") or not os.path.exists(summary):
            continue
        with open(os.path.join(d, "trial.json")) as f:
            trial = json.load(f)
        with open(summary) as f:
            yield trial["trial"], json.load(f)


def main(folders):
    out = ["| experiment | method | trials | attempts | successful | success % | successful views / trial (min–max) "
           "| stops | most start_in_collision in a stop | stops losing > 1 | start repairs | stop ends | failures by cause "
           "| success % past the view's own refusals | scripted views refused at planning (not attempts) |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    total_attempts = total_ok = worst_stop = bad_stops = total_refused = 0
    refusals = ("no_ik", "goal_in_collision")
    for folder in folders:
        groups = {}
        for trial, s in trials(folder):
            groups.setdefault(trial["label"], []).append(s)
        for label, runs in groups.items():
            attempts = sum(s["views_attempted"] for s in runs)
            ok = sum(s["views_successful"] for s in runs)
            per_trial = [s["views_successful"] for s in runs]
            stops = [st for s in runs for st in s["stops"]]
            sic = [st.get("failures", {}).get("start_in_collision", 0) for st in stops]
            ends = Counter(st.get("end", "?") for st in stops)
            repairs = sum(s.get("start_repairs", 0) for s in runs)
            causes = Counter()
            for s in runs:
                causes.update(s.get("failures", {}))
            refused = sum(causes[c] for c in refusals)
            total_refused += refused
            total_attempts += attempts
            total_ok += ok
            worst_stop = max([worst_stop] + sic)
            bad_stops += sum(1 for n in sic if n > 1)
            out.append(f"| {os.path.basename(os.path.normpath(folder))} | {label} | {len(runs)} | {attempts} | {ok} | "
                       f"{100.0 * ok / max(attempts, 1):.1f} | {sum(per_trial) / len(per_trial):.1f} "
                       f"({min(per_trial)}–{max(per_trial)}) | {len(stops)} | {max(sic) if sic else 0} | "
                       f"{sum(1 for n in sic if n > 1)} | {repairs} | "
                       + ", ".join(f"{k} {v}" for k, v in sorted(ends.items())) + " | "
                       + ", ".join(f"{k} {v}" for k, v in sorted(causes.items())) + " | "
                       f"{100.0 * ok / max(attempts - refused, 1):.1f} | {sum(s.get('refused', 0) for s in runs)} |")
    rate = 100.0 * total_ok / max(total_attempts, 1)
    out.append("")
    out.append(f"All: {total_ok} of {total_attempts} attempts succeeded ({rate:.1f} %; check: at least 95 %: "
               f"{'met' if rate >= 95.0 else 'NOT met'}); the most attempts a stop lost to start_in_collision: "
               f"{worst_stop} (check: at most 1: {'met' if worst_stop <= 1 else 'NOT met'}; stops over: {bad_stops}). "
               f"Past the views' own refusals (no_ik, goal_in_collision: {total_refused} attempts): "
               f"{100.0 * total_ok / max(total_attempts - total_refused, 1):.1f} % succeeded.")
    print("\n".join(out))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: attempts.py EXPERIMENT_DIR [EXPERIMENT_DIR ...]")
    main(sys.argv[1:])
