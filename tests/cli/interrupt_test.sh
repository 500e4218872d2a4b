#!/usr/bin/env bash
# Ctrl-C (SIGINT) and SIGTERM (kill, SLURM's scancel) during every long command, at two
# moments each: early (right after the start) and mid-work (after a progress line shows that
# work was done). What each promises (docs/commands.md, "Ctrl-C and SIGTERM"):
#   mission, run, map: the work so far published, marked "complete": false (mission and run
#     with their plots), or, interrupted before anything was done, nothing and no leftovers;
#   experiment: the finished trials kept, the unfinished ones left .partial for --resume,
#     which then completes the sweep;
#   visibility: nothing published and nothing left behind.
# Always exit code 130 (SIGINT) or 143 (SIGTERM), never a .lock or a stray .partial.
# The Python commands (map-bag, export-bag, run_mission) have python/tests/test_interrupts.py.
# Usage: interrupt_test.sh path/to/canopy
set -u
canopy="$(realpath "$1")"
src=$(pwd)
tmp=$(mktemp -d)
pid=""
cleanup() {
  [[ -n "$pid" ]] && { pkill -9 -P "$pid" 2>/dev/null; kill -9 "$pid" 2>/dev/null; }
  rm -rf "$tmp"
}
trap cleanup EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
wait_for_line() {  # wait_for_line LOG PATTERN: up to 120 s
  for _ in $(seq 1 1200); do grep -q -- "$2" "$1" 2>/dev/null && return 0; kill -0 "$pid" 2>/dev/null || return 1; sleep 0.1; done
  return 1
}
# interrupt NAME SIGNAL MOMENT PATTERN -- COMMAND...: runs the command in the background, sends
# SIGNAL at its first output line (MOMENT early) or once PATTERN is in its output (mid), and
# sets $code and $log.
interrupt() {
  local name=$1 sig=$2 moment=$3 pattern=$4
  shift 5
  log="$tmp/$name.log"
  "$@" > "$log" 2>&1 &
  pid=$!
  # Early: as soon as canopy has printed anything (it runs main(): a signal before that would
  # meet the SIGINT this non-interactive shell's background jobs start with ignored).
  if [[ $moment == early ]]; then
    wait_for_line "$log" "." || fail "$name: no output: $(tail -2 "$log")"
  elif ! wait_for_line "$log" "$pattern"; then
    fail "$name: '$pattern' never appeared: $(tail -2 "$log")"
  fi
  kill "-$sig" "$pid" 2>/dev/null
  wait "$pid"
  code=$?
  pid=""
  local want=130
  [[ $sig == TERM ]] && want=143
  [[ $code -eq $want ]] || fail "$name: exit $code after SIG$sig (want $want): $(tail -2 "$log")"
}
no_leftovers() {  # no .partial, .lock or .old.tmp beside $1
  local left
  left=$(ls -d "$1".partial "$1".lock "$1".old.tmp* 2>/dev/null)
  [[ -z "$left" ]] || fail "$2: left behind: $left"
}
complete_is() {  # complete_is FILE.json true|false NAME
  local got
  got=$(python3 -c 'import json,sys; print(str(json.load(open(sys.argv[1]))["complete"]).lower())' "$1" 2>&1)
  [[ "$got" == "$2" ]] || fail "$3: $1 says complete: $got (want $2)"
}
# The promise of mission, run and map: the work so far, incomplete; or nothing at all.
saved_or_nothing() {  # saved_or_nothing DIR RESULT.json NAME MOMENT [FILES...]
  local dir=$1 json=$2 name=$3 moment=$4
  shift 4
  no_leftovers "$dir" "$name"
  if [[ -d "$dir" ]]; then
    complete_is "$dir/$json" false "$name"
    for f in "$@"; do [[ -s "$dir/$f" ]] || fail "$name: the saved run lacks $f"; done
  elif [[ $moment == mid ]]; then
    fail "$name: interrupted mid-work, nothing was saved: $(tail -2 "$log")"
  else
    grep -q "nothing was written\|^canopy: interrupted$\|^canopy: terminated$" "$log" ||
      fail "$name: nothing saved and no line saying so: $(tail -2 "$log")"
  fi
}
nothing_left() {  # nothing_left DIR NAME
  [[ ! -e "$1" ]] || fail "$2: interrupted, but $1 was published"
  no_leftovers "$1" "$2"
}

# --- mission and run (the views so far, marked incomplete, with their plots) ----------------
for sig in INT TERM; do
  for moment in early mid; do
    out="$tmp/mission_${sig}_$moment"
    interrupt "mission_${sig}_$moment" "$sig" "$moment" "initial view 3 " -- \
      "$canopy" mission --world worlds/small.yaml --views-per-stop 8 --out "$out"
    saved_or_nothing "$out" summary.json "mission $sig $moment" "$moment" views.csv map.csm sc_entropy.svg report.html
    out="$tmp/run_${sig}_$moment"
    interrupt "run_${sig}_$moment" "$sig" "$moment" "initial view 3 " -- \
      "$canopy" run --world worlds/small.yaml --views-per-stop 8 --no-report --out "$out"
    saved_or_nothing "$out" summary.json "run $sig $moment" "$moment" views.csv runtime.svg
  done
done

# --- map (the views so far, metrics.json incomplete) ------------------------------------------
for sig in INT TERM; do
  for moment in early mid; do
    out="$tmp/map_${sig}_$moment"
    interrupt "map_${sig}_$moment" "$sig" "$moment" "view 3/" -- \
      "$canopy" map --world worlds/small.yaml --views aisle --out "$out"
    saved_or_nothing "$out" metrics.json "map $sig $moment" "$moment" map.csm
  done
done

# --- experiment (finished trials kept, unfinished ones .partial; --resume completes it) -------
cat > "$tmp/exp.yaml" <<YAML
name: interrupt
world: $src/worlds/small.yaml
overrides:
  mission: {loop: {views_per_stop: 6}}
methods:
  - {label: ours, method: ours}
p_gt: [1.0]
seeds: [1, 2, 3]
trial_timeout_s: 300
YAML
for sig in INT TERM; do
  for moment in early mid; do
    out="$tmp/exp_${sig}_$moment"
    name="experiment $sig $moment"
    interrupt "exp_${sig}_$moment" "$sig" "$moment" "\[1/3\]" -- \
      "$canopy" experiment --config "$tmp/exp.yaml" --out "$out" --jobs 1
    [[ -z "$(ls "$out".lock "$out"/trials/*.lock 2>/dev/null)" ]] || fail "$name: lock files left"
    if [[ $moment == mid ]]; then
      [[ -f "$out/trials/ours_pgt1_seed1/trial.json" ]] || fail "$name: the finished trial was not kept"
      [[ -d "$out/trials/ours_pgt1_seed2.partial" ]] || fail "$name: the running trial is not left .partial"
    fi
    if [[ -d "$out" || -d "$out.partial" ]]; then
      "$canopy" experiment --config "$tmp/exp.yaml" --out "$out" --jobs 2 --resume > "$tmp/resume.log" 2>&1 ||
        fail "$name: --resume failed: $(tail -2 "$tmp/resume.log")"
      [[ $(ls -d "$out"/trials/*/ 2>/dev/null | grep -vc '\.partial/$') -eq 3 ]] ||
        fail "$name: --resume did not complete the sweep: $(ls "$out/trials")"
    fi
  done
done

# --- report ---------------------------------------------------------------------------------
# Not signalled here any more: since the figures are drawn in C++ (issue 46 point 8) a 3-trial
# report takes about 20 ms after its first output line, so a signal sent on that line arrives
# after the report is published. Its stop checks (jobs::write_report, before writing and before
# publishing) need a test that does not depend on timing: an open item (closing note, 5 Dec).

# --- visibility (nothing published, nothing left) ---------------------------------------------
for sig in INT TERM; do
  for moment in early mid; do
    out="$tmp/vis_${sig}_$moment"
    interrupt "vis_${sig}_$moment" "$sig" "$moment" "seed 1:" -- "$canopy" visibility --seed 1,2,3 --out "$out"
    nothing_left "$out" "visibility $sig $moment"
  done
done

if ((failures)); then
  echo "$failures failure(s)"
  exit 1
fi
echo "interrupt test: ok"
