#!/usr/bin/env bash
# canopy experiment / canopy report from the command line with real missions on the small
# world: bad input is a clean error; two shards run as two processes by GNU parallel into one
# folder run every trial exactly once and give the same curves as one process running all;
# the report of two shard folders equals the report of one folder holding both; a sweep killed
# mid-trial leaves only complete trials or .partial folders, the report lists what is missing,
# and --resume completes it with the same results; other settings on --resume are an error
# naming the trial and the setting; a trial with different results in two folders is an error.
set -euo pipefail
canopy="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
command -v parallel >/dev/null || { echo "GNU parallel is missing (tools/deps.sh installs it)"; exit 1; }

exp="$dir/tiny.yaml"
cat > "$exp" <<YAML
name: tiny
world: $PWD/worlds/small.yaml
overrides:
  mission: {loop: {views_per_stop: 1}, scan: {heights_m: [0.85], azimuths_deg: [0.0], extra_heights_m: [0.55]}}
methods:
  - {label: ours, method: ours}
  - {label: predefined, method: predefined}
p_gt: [1.0, 0.7]
seeds: [1]
trial_timeout_s: 120
YAML
ids=$(python3 - <<'PY'
print(" ".join(f"{m}_pgt{p}_seed{s}" for s in (1,) for p in ("1", "0.7") for m in ("ours", "predefined")))
PY
)

fail() { echo "experiment cli: $*"; exit 1; }
expect_error() {  # expect_error WORD args...: exit 2, one error line naming WORD
  local word=$1; shift
  set +e
  msg=$("$canopy" "$@" 2>&1 >/dev/null)
  code=$?
  set -e
  [[ $code -eq 2 ]] || fail "$*: exit $code, expected 2 ($msg)"
  [[ "$msg" == *"$word"* ]] || fail "$*: message does not name $word: $msg"
  [[ $(echo "$msg" | grep -c "error") -eq 1 ]] || fail "$*: not one error line: $msg"
}

# Bad input.
{ cat "$exp"; echo "sedes: [3]"; } > "$dir/bad.yaml"
expect_error sedes experiment --config "$dir/bad.yaml" --out "$dir/bad"
expect_error "no-such.yaml" experiment --config "$dir/no-such.yaml" --out "$dir/bad"
expect_error "--shard" experiment --config "$exp" --out "$dir/bad" --shard 2/2
expect_error "--jobs" experiment --config "$exp" --out "$dir/bad" --jobs 0
expect_error "experiment.json" report "$dir"
[[ ! -e "$dir/bad" ]] || fail "a bad command left an output folder"

# GNU parallel: two shards as two processes into one folder (as across ssh hosts with a shared folder).
parallel --will-cite --jobs 2 "$canopy" experiment --config "$exp" --out "$dir/par" --shard {}/2 --resume ::: 0 1 \
  2> "$dir/par.log" || { cat "$dir/par.log"; fail "parallel run failed"; }
for id in $ids; do
  [[ -f "$dir/par/trials/$id/trial.json" ]] || fail "parallel: trial $id missing"
  n=$(grep -c "trial $id: started" "$dir/par.log")
  [[ $n -eq 1 ]] || fail "parallel: trial $id started $n times"
done
[[ $(ls "$dir/par/trials" | wc -l) -eq 4 ]] || fail "parallel: not 4 trial folders: $(ls "$dir/par/trials")"

# One process running everything gives the same curves (missions are deterministic per seed).
"$canopy" experiment --config "$exp" --out "$dir/full" --jobs 2 2> "$dir/full.log"
"$canopy" report "$dir/par" --no-plots 2>/dev/null
"$canopy" report "$dir/full" 2>/dev/null
cmp "$dir/par/report/curves.csv" "$dir/full/report/curves.csv" || fail "shards and one process differ in curves.csv"
for f in curves.csv runtime.csv findings.md trials.json fig3_entropy_coverage.svg fig4_runtime.svg; do
  [[ -s "$dir/full/report/$f" ]] || fail "report: missing $f"
done
grep -q "4 expected, 4 ok, 0 failed, 0 missing" "$dir/full/report/findings.md" || fail "findings: $(head -3 "$dir/full/report/findings.md")"

# Two shard folders merged equal one folder holding both shards.
for s in a b; do mkdir -p "$dir/$s/trials"; cp "$dir/par/experiment.json" "$dir/par/.canopy-output" "$dir/$s/"; done
for id in $ids; do
  shard=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["shard"])' "$dir/par/trials/$id/trial.json")
  [[ $shard == 0/2 ]] && cp -r "$dir/par/trials/$id" "$dir/a/trials/" || cp -r "$dir/par/trials/$id" "$dir/b/trials/"
done
"$canopy" report "$dir/a" "$dir/b" --out "$dir/r_ab" --no-plots 2>/dev/null
for f in curves.csv runtime.csv findings.md; do
  cmp "$dir/r_ab/$f" "$dir/par/report/$f" || fail "merged shards differ from one folder in $f"
done
"$canopy" report "$dir/a" --out "$dir/r_a" --no-plots 2>/dev/null
[[ $(grep -c "^- missing: " "$dir/r_a/findings.md") -eq 2 ]] || fail "one shard alone: not 2 missing trials listed"

# A trial with different results in two folders is an error.
python3 - "$dir/b/trials/predefined_pgt1_seed1/mission/views.csv" <<'PY'  # trial 1: shard 1
import sys
lines = open(sys.argv[1]).read().splitlines()
head = lines[0].split(",")
row = lines[-1].split(",")
row[head.index("coverage")] = "0.999"
lines[-1] = ",".join(row)
open(sys.argv[1], "w").write("\n".join(lines) + "\n")
PY
expect_error "predefined_pgt1_seed1" report "$dir/par" "$dir/b" --out "$dir/r_bad"

# A sweep killed mid-trial (SIGTERM, as scancel sends): only complete trials or .partial ones.
"$canopy" experiment --config "$exp" --out "$dir/kill" --jobs 2 2> "$dir/kill.log" &
pid=$!
for _ in $(seq 1 300); do grep -q "\[1/4\]" "$dir/kill.log" && break; sleep 0.1; done
kill -TERM "$pid"
set +e
wait "$pid"
code=$?
set -e
[[ $code -eq 143 ]] || { cat "$dir/kill.log"; fail "killed sweep (SIGTERM): exit $code, expected 143"; }
complete=0
for t in "$dir/kill/trials"/*; do
  case "$t" in
    *.partial) ;;
    *) [[ -f "$t/trial.json" && -f "$t/mission/views.csv" ]] || fail "half-written trial $t"; complete=$((complete + 1)) ;;
  esac
done
(( complete >= 1 && complete < 4 )) || fail "killed sweep: $complete complete trials"
"$canopy" report "$dir/kill" --no-plots 2>/dev/null
missing=$(grep -c "^- missing: " "$dir/kill/report/findings.md" || true)
[[ $missing -eq $((4 - complete)) ]] || fail "report lists $missing missing trials, expected $((4 - complete))"
# Also a trial left .partial by hand (a kill between the mission and the rename).
mv "$dir/kill/trials/predefined_pgt1_seed1" "$dir/kill/trials/predefined_pgt1_seed1.partial" 2>/dev/null || true
"$canopy" experiment --config "$exp" --out "$dir/kill" --jobs 2 --resume 2> "$dir/resume.log"
grep -q "complete already" "$dir/resume.log" || fail "resume: no skip count"
[[ $(ls "$dir/kill/trials" | grep -c partial || true) -eq 0 ]] || fail "resume left .partial folders"
for id in $ids; do
  cmp "$dir/kill/trials/$id/mission/views.csv" "$dir/full/trials/$id/mission/views.csv" || fail "resumed $id differs"
done
"$canopy" report "$dir/kill" --no-plots 2>/dev/null
grep -q "4 expected, 4 ok, 0 failed, 0 missing; 0 incomplete" "$dir/kill/report/findings.md" || fail "resumed report incomplete"

# Other settings on --resume: an error naming the trial and the setting; without --resume the folder is kept.
sed 's/views_per_stop: 1/views_per_stop: 2/' "$exp" > "$dir/other.yaml"
expect_error "settings.mission.loop.views_per_stop" experiment --config "$dir/other.yaml" --out "$dir/full" --resume
expect_error "_seed" experiment --config "$dir/other.yaml" --out "$dir/full" --resume
expect_error "--resume" experiment --config "$exp" --out "$dir/full"
echo "experiment cli: ok (bad input, GNU parallel shards, merge, conflict, kill + resume ($complete of 4 complete when killed), mismatch)"
