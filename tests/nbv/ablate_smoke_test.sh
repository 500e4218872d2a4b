#!/usr/bin/env bash
# Smoke test of `canopy ablate --quick`: it runs, writes its outputs, and its results do not
# depend on the number of worker threads (timings aside).
set -euo pipefail
canopy="$1"
dir="$2"
rm -rf "$dir"
# Bad input: exit code 2, a message naming the option, no output folder.
for bad in "--gains osamcep,entropy" "--rays ours,all" "--pgt 1.5" "--plants 99"; do
  set +e
  msg=$("$canopy" ablate --quick $bad --out "$dir/bad" 2>&1 >/dev/null)
  code=$?
  set -e
  [[ $code -eq 2 ]] || { echo "ablate $bad: exit $code, expected 2"; exit 1; }
  [[ "$msg" == *"${bad%% *}"* ]] || { echo "ablate $bad: message does not name the option: $msg"; exit 1; }
  [[ ! -e "$dir/bad" ]] || { echo "ablate $bad: left an output folder"; exit 1; }
done
"$canopy" ablate --quick --views 4 --no-plots --threads 1 --out "$dir/t1" > /dev/null 2>&1
"$canopy" ablate --quick --views 4 --no-plots --threads 2 --out "$dir/t2" > /dev/null 2>&1
for f in summary.csv table.csv run.yaml settings.yaml; do
  [[ -s "$dir/t2/$f" ]] || { echo "missing $f"; exit 1; }
done
python3 - "$dir/t1" "$dir/t2" <<'PY'
import json, pathlib, sys
a, b = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if not k.startswith("ms_")}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
files = sorted(p.relative_to(a) for p in (a / "jobs").rglob("*.json"))
assert len(files) == 3, files
for f in files:
    ja, jb = strip(json.loads((a / f).read_text())), strip(json.loads((b / f).read_text()))
    assert ja == jb, f"{f} differs between 1 and 2 threads"
    assert len(ja["steps"]) == 4
    assert all(0.0 <= s["coverage"] <= 1.0 for s in ja["steps"])
print("ablate smoke: ok,", len(files), "jobs identical with 1 and 2 threads")
PY
