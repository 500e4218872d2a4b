#!/usr/bin/env python3
"""The arm's contacts with the true plants on the drives between stops (docs/experiments/arm_on_drive).

Each argument is LABEL=RUN, a `canopy experiment` --out folder whose summaries count
arm_drive_truth_contacts and arm_home_truth_contacts per stop. Prints per method, for each run:
the drives (every stop's, the first from the aisle's start), those on which the arm touched the true plants at a check of the
base and the contact checks in all, then the moves home before a drive that touched them and their
contact checks (executed arm states).

  python3 docs/experiments/arm_on_drive/contacts.py hold=runs/contacts_hold_dense clear=runs/contacts_clear_dense
"""
import json
import pathlib
import sys

METHODS = ["learned", "shape", "frontier", "global", "reveal", "ours", "predefined", "oracle"]


def main():
    if len(sys.argv) < 2 or any("=" not in a for a in sys.argv[1:]):
        sys.exit("usage: contacts.py LABEL=RUN [LABEL=RUN ...]")
    runs = [a.split("=", 1) for a in sys.argv[1:]]
    table = {}
    for label, run in runs:
        trials = pathlib.Path(run) / "trials"
        if not trials.is_dir():
            sys.exit(f"contacts.py: {trials} is not a folder")
        for t in sorted(trials.iterdir()):
            if not (t / "trial.json").is_file():
                continue
            method = json.loads((t / "trial.json").read_text())["trial"]["label"]
            stops = json.loads((t / "mission" / "summary.json").read_text())["stops"]
            if any("arm_drive_truth_contacts" not in s for s in stops):
                sys.exit(f"contacts.py: {t} has no arm_drive_truth_contacts (an older canopy)")
            for s in stops:  # a stop whose arm was held made no move home
                if "arm_home_truth_contacts" not in s:
                    if s.get("arm_on_drive") != "held":
                        sys.exit(f"contacts.py: {t} has no arm_home_truth_contacts (an older canopy)")
                    s["arm_home_truth_contacts"] = 0
            r = table.setdefault((label, method), [0, 0, 0, 0, 0])
            for s in stops:
                r[0] += 1
                r[1] += s["arm_drive_truth_contacts"] > 0
                r[2] += s["arm_drive_truth_contacts"]
                r[3] += s["arm_home_truth_contacts"] > 0
                r[4] += s["arm_home_truth_contacts"]
    labels = [label for label, _ in runs]
    print("| method | drives | " + " | ".join(f"{l}: drives touching | checks | moves home touching | checks"
                                              for l in labels) + " |")
    print("|---|---|" + "---|---|---|---|" * len(labels))
    methods = METHODS + sorted({m for _, m in table} - set(METHODS))
    totals = {l: [0, 0, 0, 0, 0] for l in labels}
    for m in methods:
        if not any((l, m) in table for l in labels):
            continue
        cells = []
        for l in labels:
            r = table.get((l, m), [0, 0, 0, 0, 0])
            totals[l] = [a + b for a, b in zip(totals[l], r)]
            cells.append(f"{r[1]} | {r[2]} | {r[3]} | {r[4]}")
        print(f"| {m} | {table.get((labels[0], m), [0])[0]} | " + " | ".join(cells) + " |")
    print(f"| all | {totals[labels[0]][0]} | " +
          " | ".join(f"{totals[l][1]} | {totals[l][2]} | {totals[l][3]} | {totals[l][4]}" for l in labels) + " |")


if __name__ == "__main__":
    main()
