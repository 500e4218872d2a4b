#!/usr/bin/env python3
"""The arm planner's iteration budget read off recorded missions (issue 49 A).

Every attempt's timing.csv row holds the OMPL iterations of the plan that decided it
(`plan_iterations`; 0 when no search ran). A request with the same seed and a budget of at least
that many gives the same outcome (ArmPlannerTest.RecordedIterationsDecideTheOutcomeUnderAnyBudget),
so for any smaller budget B the searched plans that succeeded with more than B iterations are
exactly the verdicts B changes, and a search that ran out of the recorded budget would stop
after B iterations instead.

  tools/plan_budget.py RUN_FOLDER_OR_EXPERIMENT... [--budgets 1000,2000,...] [--max 20000]

Each argument is a mission folder (views.csv + timing.csv) or any folder above such folders
(an experiment's trials). Prints the curve (quantiles of the iterations successful searched
plans needed), for each budget the share of them lost and the seconds the failed searches would
take, and the smallest budget losing at most 0.5 %.
"""
import argparse
import csv
import math
import os
import sys


def missions(paths):
    for p in paths:
        for root, dirs, files in os.walk(p):
            dirs.sort()
            if "views.csv" in files and "timing.csv" in files:
                yield root


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("paths", nargs="+")
    ap.add_argument("--budgets", default="500,1000,1500,2000,3000,4000,5000,7500,10000,15000,20000")
    ap.add_argument("--max", type=int, default=20000, help="the budget the missions ran with")
    ap.add_argument("--lost", type=float, default=0.005, help="the share of successful plans a budget may lose")
    a = ap.parse_args()
    budgets = [int(b) for b in a.budgets.split(",")]
    ok_iters, fail_iters, fail_secs, ok_secs = [], [], [], []
    by_method = {}
    views = attempts = searched = 0
    n_missions = 0
    for m in missions(a.paths):
        n_missions += 1
        v = {r["attempt"]: r for r in read_rows(os.path.join(m, "views.csv"))}
        t = read_rows(os.path.join(m, "timing.csv"))
        if not t or "plan_iterations" not in t[0]:
            sys.exit(f"{m}/timing.csv has no plan_iterations column (recorded before issue 49)")
        for r in t:
            attempts += 1
            view = v[r["attempt"]]
            views += view["success"] in ("1", "true")
            it = int(r["plan_iterations"])
            if it == 0:
                continue
            searched += 1
            method = view.get("method", "?")
            planned = view["failure"] != "plan_timeout"
            secs = float(r["motion_planning_s"])
            by_method.setdefault(method, [0, 0, 0])
            by_method[method][0] += 1
            if planned:
                ok_iters.append(it)
                ok_secs.append(secs)
                by_method[method][1] += 1
            else:
                fail_iters.append(it)
                fail_secs.append(secs)
                by_method[method][2] += 1
    ok_iters.sort()
    n = len(ok_iters)
    print(f"{n_missions} missions, {attempts} attempts, {views} successful views, {searched} searched plans: "
          f"{n} successful, {len(fail_iters)} out of budget ({sum(fail_secs):.1f} s of motion planning in their attempts)")
    for method, (s, o, f) in sorted(by_method.items()):
        print(f"  {method}: {s} searched, {o} successful, {f} out of budget")
    if not n:
        return
    def q(p):
        return ok_iters[min(n - 1, max(0, math.ceil(p * n) - 1))]
    print("iterations successful searched plans needed: " +
          ", ".join(f"{int(p * 1000) / 10:g} % <= {q(p)}" for p in (0.5, 0.9, 0.95, 0.99, 0.995, 1.0)))
    per_iter = sum(fail_secs) / max(1, sum(fail_iters))
    print(f"failed searches: {per_iter * 1e3:.3f} ms per iteration (their attempts' motion planning / iterations)")
    print("budget | successful plans lost | share | verdicts changed per 1,000 views | a failed search, s")
    chosen = None
    for b in budgets:
        lost = sum(1 for i in ok_iters if i > b)
        share = lost / n
        if chosen is None and share <= a.lost:
            chosen = b
        print(f"{b} | {lost} | {100 * share:.2f} % | {1000 * lost / max(1, views):.2f} | {per_iter * min(b, a.max):.2f}")
    print(f"smallest listed budget losing at most {100 * a.lost:g} %: {chosen}")


if __name__ == "__main__":
    main()
