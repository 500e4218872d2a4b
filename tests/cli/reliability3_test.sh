#!/usr/bin/env bash
# Reliability, third pass (issue 31), from the command line with real processes: outputs inside
# --out, the figures (item 4: in-process now), an encoder that never reads, two runs on one video, trial locks and
# children that die with the experiment, nbv --out, a dangling-symlink --out, stderr piped
# into head, a commit killed between its renames, I/O errors, a planted lock symlink, a report
# killed (item 14: no plot child any more), a bad CANOPY_DATA_DIR. Numbered as the issue's items.
# Usage: reliability3_test.sh path/to/canopy
set -u
canopy="$(realpath "$1")"
tmp=$(mktemp -d)
background=()
cleanup() {
  for p in "${background[@]}"; do pkill -9 -P "$p" 2>/dev/null; kill -9 "$p" 2>/dev/null; done
  rm -rf "$tmp"
}
trap cleanup EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect_2 FRAGMENT COMMAND...: exit code 2 and exactly one error line, which names FRAGMENT.
expect_2() {
  local fragment="$1"
  shift
  local msg code errors
  msg=$("$@" 2>&1 >/dev/null)
  code=$?
  errors=$(grep -c "error" <<<"$msg")
  [[ $code -eq 2 ]] || fail "$*: exit $code (want 2): $(tail -2 <<<"$msg")"
  [[ "$errors" -eq 1 && "$(grep error <<<"$msg")" == *"$fragment"* ]] ||
    fail "$*: want one error line naming '$fragment', got: $(tail -3 <<<"$msg")"
}
# wait_for CONDITION-COMMAND...: polls up to 60 s.
wait_for() {
  for _ in $(seq 1 600); do "$@" && return 0; sleep 0.1; done
  return 1
}
gone() { ! kill -0 "$1" 2>/dev/null; }
no_leftovers() {  # no .partial, .lock or .old.tmp beside $1
  local left
  left=$(ls -d "$1".partial "$1".lock "$1".old.tmp* 2>/dev/null)
  [[ -z "$left" ]] || fail "$2: left $left"
}

small=worlds/small.yaml
quick=(mission --world "$small" --no-plots --views-per-stop 0)
"$canopy" "${quick[@]}" --out "$tmp/base" >/dev/null 2>&1 || fail "a quick mission"
summary_sum=$(sha256sum < "$tmp/base/summary.json")

# --- 3. An export or a video inside --out is refused before the run, not deleted. ----------
cp -r "$tmp/base" "$tmp/o6"
cp -r "$tmp/base" "$tmp/o8"
expect_2 "--export: '$tmp/o6/ds' is inside" "$canopy" "${quick[@]}" --out "$tmp/o6" --export "$tmp/o6/ds"
expect_2 "--video: '$tmp/o8/run.mp4' is inside" "$canopy" "${quick[@]}" --out "$tmp/o8" --video "$tmp/o8/run.mp4"
expect_2 "--export" "$canopy" "${quick[@]}" --out "$tmp/o7" --export "$tmp/o7"
[[ -s "$tmp/o6/summary.json" && ! -e "$tmp/o6/ds" && ! -e "$tmp/o7" ]] || fail "item 3 touched its folders"
[[ "$(sha256sum < "$tmp/o8/summary.json")" == "$summary_sum" && ! -e "$tmp/o8/run.mp4" ]] || fail "item 3 replaced o8"
printf '0.0 0.3 0.7 0.5 -0.5 0.5 -0.5\n' > "$tmp/one_view.txt"
expect_2 "--export: '$tmp/o9/ds' is inside" "$canopy" map --views "$tmp/one_view.txt" --out "$tmp/o9" --export "$tmp/o9/ds"
# Nor inside another command's folder, which its next run replaces.
expect_2 "the output of \`canopy mission\`" "$canopy" map --views "$tmp/one_view.txt" --out "$tmp/base/m"

# --- 9. A dangling-symlink --out is refused before the run. ---------------------------------
ln -s "$tmp/nowhere" "$tmp/link"
log=$("$canopy" "${quick[@]}" --out "$tmp/link" 2>&1); code=$?
[[ $code -eq 2 && "$log" == *"'$tmp/link' is a symbolic link to '$tmp/nowhere', which does not exist"* ]] ||
  fail "dangling --out: exit $code: $(tail -1 <<<"$log")"
[[ "$log" != *"mission done"* && ! -e "$tmp/nowhere" ]] || fail "dangling --out: the mission ran"

# --- 13. A planted lock symlink makes canopy write nothing at its target. ------------------
ln -s "$tmp/victim" "$tmp/o13.lock"
expect_2 "the lock file '$tmp/o13.lock' is a symbolic link" "$canopy" "${quick[@]}" --out "$tmp/o13"
[[ ! -e "$tmp/victim" && ! -e "$tmp/o13" && ! -e "$tmp/o13.partial" ]] || fail "a lock symlink wrote outside --out"

# --- 8. canopy nbv --out never overwrites its input or a file it did not write. -------------
"$canopy" map --views "$tmp/one_view.txt" --out "$tmp/m8" >/dev/null 2>&1 || fail "map for item 8"
map_sum=$(sha256sum < "$tmp/m8/map.csm")
expect_2 "is the input --map" "$canopy" nbv --map "$tmp/m8/map.csm" --base 0,0,0 --out "$tmp/m8/map.csm"
cp "$tmp/one_view.txt" "$tmp/mine.json"
expect_2 "is not a views file canopy nbv wrote" "$canopy" nbv --map "$tmp/m8/map.csm" --base 0,0,0 --out "$tmp/mine.json"
[[ "$(sha256sum < "$tmp/m8/map.csm")" == "$map_sum" ]] && cmp -s "$tmp/one_view.txt" "$tmp/mine.json" ||
  fail "nbv --out overwrote a file"

# --- 10. stderr piped into head: the run goes on and publishes its folder. ------------------
"$canopy" mission --world "$small" --no-plots --views-per-stop 1 --out "$tmp/o10" 2>&1 | head -1 >/dev/null
code=${PIPESTATUS[0]}
[[ $code -eq 0 && -s "$tmp/o10/summary.json" ]] || fail "mission | head -1: exit $code (141 is death by SIGPIPE)"
no_leftovers "$tmp/o10" "mission | head"

# --- 11. A commit killed between its renames is finished by the next run. ------------------
cp -r "$tmp/base" "$tmp/o11"
CANOPY_FAULT=after_first_rename "$canopy" "${quick[@]}" --out "$tmp/o11" >/dev/null 2>&1
code=$?
[[ $code -eq 137 && ! -e "$tmp/o11" && -d "$tmp/o11.partial" && -n "$(ls -d "$tmp"/o11.old.tmp* 2>/dev/null)" ]] ||
  fail "the fault hook did not leave the commit window (exit $code)"
"$canopy" "${quick[@]}" --out "$tmp/o11" >/dev/null 2>&1 || fail "the run after a killed commit"
complete() { python3 -c 'import json,sys; sys.exit(0 if json.load(open(sys.argv[1]))["complete"] else 1)' "$1/summary.json"; }
complete "$tmp/o11" || fail "the run after a killed commit did not publish a complete folder"
no_leftovers "$tmp/o11" "the run after a killed commit"

# --- 12. I/O errors: one line, exit 2, nothing staged left behind. --------------------------
msg=$( (ulimit -f 4; "$canopy" world --world "$small" --out "$tmp/w12") 2>&1 >/dev/null); code=$?
[[ $code -eq 2 && "$msg" == *"File too large"* && $(grep -c error <<<"$msg") -eq 1 ]] ||
  fail "world past ulimit -f: exit $code: $msg"
[[ ! -e "$tmp/w12" ]] || fail "world past ulimit -f left $tmp/w12"
no_leftovers "$tmp/w12" "world past ulimit -f"
if command -v strace >/dev/null && strace -f -qq -o /dev/null true 2>/dev/null; then
  # The staging folder cannot be made (ENOSPC injected into mkdir): no .partial, no .lock.
  # LeakSanitizer cannot run under ptrace, so a sanitizer build checks leaks elsewhere.
  msg=$(ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" strace -f -qq -o /dev/null -e trace=mkdir,mkdirat -e inject=mkdir,mkdirat:error=ENOSPC \
        "$canopy" world --world "$small" --out "$tmp/w12b" 2>&1 >/dev/null); code=$?
  [[ $code -eq 2 && "$msg" == *"No space left on device"* ]] || fail "world with mkdir failing: exit $code: $msg"
  no_leftovers "$tmp/w12b" "world with mkdir failing"
else
  echo "note: strace cannot trace here; the mkdir-failure check is skipped"
fi

# --- 17. A bad CANOPY_DATA_DIR is named. ----------------------------------------------------
mkdir -p "$tmp/elsewhere"
msg=$(cd "$tmp/elsewhere" && CANOPY_DATA_DIR="$tmp/nowhere" "$canopy" world --out w 2>&1 >/dev/null); code=$?
[[ $code -eq 2 && "$msg" == *"CANOPY_DATA_DIR: '$tmp/nowhere' is not canopy's data folder"* ]] ||
  fail "bad CANOPY_DATA_DIR: exit $code: $msg"

# --- 5 and 6. An encoder that never reads: SIGTERM ends the run (143); a second run on the --
# --- same video is refused as busy; with a stall timeout the run ends without the video. ---
mkdir -p "$tmp/bin"
printf '#!/bin/sh\necho $$ > "%s/ffmpeg.pid"\nexec sleep 600\n' "$tmp" > "$tmp/bin/ffmpeg"
chmod +x "$tmp/bin/ffmpeg"
PATH="$tmp/bin:$PATH" "$canopy" mission --world "$small" --no-plots --views-per-stop 2 --video "$tmp/v.mp4" \
  --out "$tmp/o5" > "$tmp/o5.log" 2>&1 &
mission=$!
background+=("$mission")
wait_for test -s "$tmp/ffmpeg.pid" || fail "the fake ffmpeg did not start"
expect_2 "--video: '$tmp/v.mp4' is busy" "$canopy" "${quick[@]}" --video "$tmp/v.mp4" --out "$tmp/o6b"
sleep 2  # (any time: the frames fill the encoder's input within a second, and block there)
kill -TERM "$mission"
wait_for gone "$mission" || { fail "SIGTERM did not stop a mission whose encoder never reads (60 s)"; kill -9 "$mission"; }
wait "$mission"
code=$?
[[ $code -eq 143 ]] || fail "SIGTERM with a stuck encoder: exit $code (want 143): $(tail -2 "$tmp/o5.log")"
wait_for gone "$(cat "$tmp/ffmpeg.pid")" || { fail "the stuck encoder outlived the mission"; kill -9 "$(cat "$tmp/ffmpeg.pid")"; }
[[ ! -e "$tmp/v.mp4" && ! -e "$tmp/v.mp4.partial.mp4" && ! -e "$tmp/v.mp4.lock" ]] || fail "a stuck encoder left video files"
rm -f "$tmp/ffmpeg.pid"
msg=$(CANOPY_VIDEO_STALL_S=1 PATH="$tmp/bin:$PATH" timeout 120 "$canopy" mission --world "$small" --no-plots \
      --views-per-stop 1 --video "$tmp/v2.mp4" \
      --out "$tmp/o5b" 2>&1 >/dev/null); code=$?
[[ $code -eq 1 && "$msg" == *"the video $tmp/v2.mp4 is missing"*"read nothing for 1 s"* ]] ||
  fail "a stuck encoder without a signal: exit $code (want 1, the video missing): $(tail -2 <<<"$msg")"
[[ -s "$tmp/o5b/summary.json" ]] || fail "a stuck encoder cost the run its results"
wait_for gone "$(cat "$tmp/ffmpeg.pid")" || { fail "the stalled encoder outlived the mission"; kill -9 "$(cat "$tmp/ffmpeg.pid")"; }

# --- An experiment of one trial for items 7 and 4. ------------------------------------
cat > "$tmp/one.yaml" <<YAML
name: one
world: $PWD/worlds/small.yaml
overrides:
  mission: {loop: {views_per_stop: 1}, scan: {heights_m: [0.85], azimuths_deg: [0.0], extra_heights_m: [0.55]}}
methods:
  - {label: predefined, method: predefined}
p_gt: [1.0]
seeds: [1]
trial_timeout_s: 120
YAML
"$canopy" experiment --config "$tmp/one.yaml" --out "$tmp/e" >/dev/null 2>&1 || fail "a one-trial experiment"
trial=$(ls "$tmp/e/trials" | grep -v '\.' | head -1)
[[ -n "$trial" && -s "$tmp/e/trials/$trial/trial.json" ]] || fail "the one-trial experiment wrote no trial"

# --- 7. A trial another process runs is skipped, its .partial kept. ------------------------
rm -rf "$tmp/e/trials/$trial"
mkdir -p "$tmp/e/trials/$trial.partial"
echo "in flight" > "$tmp/e/trials/$trial.partial/log.txt"
flock -o "$tmp/e/trials/$trial.lock" sleep 600 &  # -o: the lock is flock's own, not sleep's
holder=$!
background+=("$holder")
wait_for test -e "$tmp/e/trials/$trial.lock"
sleep 0.3
expect_2 "being run by another canopy experiment" "$canopy" experiment --config "$tmp/one.yaml" --out "$tmp/e" --resume
[[ "$(cat "$tmp/e/trials/$trial.partial/log.txt" 2>/dev/null)" == "in flight" ]] || fail "--resume deleted an in-flight trial"
pkill -P "$holder" sleep
kill "$holder" 2>/dev/null
wait "$holder" 2>/dev/null
"$canopy" experiment --config "$tmp/one.yaml" --out "$tmp/e" --resume >/dev/null 2>&1 || fail "--resume after the lock was freed"
[[ -s "$tmp/e/trials/$trial/trial.json" && ! -e "$tmp/e/trials/$trial.partial" ]] || fail "--resume did not run the trial"
# kill -9 of the experiment: its trial's mission dies with it (a longer trial, so that it is
# still running when the experiment is killed): SIGTERM, so it saves what it has, incomplete.
sed 's/views_per_stop: 1/views_per_stop: 8/; s/method: predefined}/method: ours}/' "$tmp/one.yaml" > "$tmp/long.yaml"
"$canopy" experiment --config "$tmp/long.yaml" --out "$tmp/e7" > /dev/null 2>&1 &
exp=$!
background+=("$exp")
child=""
find_child() { child=$(pgrep -P "$exp" | head -1); [[ -n "$child" ]]; }
wait_for find_child || fail "the experiment started no trial"
kill -9 "$exp"
wait "$exp" 2>/dev/null
[[ -z "$child" ]] || wait_for gone "$child" || { fail "the trial's mission outlived the killed experiment"; kill -9 "$child"; }
left="$tmp/e7/trials/$trial.partial/mission/summary.json"
[[ ! -f "$left" ]] || ! complete "$(dirname "$left")" || fail "the trial's mission ran to its end after the experiment was killed"

# --- 4. The figures: drawn in-process as SVG (no script, no child process to fail or outlive
# the command); --no-plots leaves them out and changes nothing else. --------------------------
"$canopy" report "$tmp/e" --out "$tmp/r" --no-plots >/dev/null 2>&1 || fail "report"
report_sum=$(sha256sum < "$tmp/r/findings.md")
[[ ! -e "$tmp/r/fig3_entropy_coverage.svg" ]] || fail "report --no-plots drew fig3_entropy_coverage.svg"
"$canopy" report "$tmp/e" --out "$tmp/r" >/dev/null 2>&1 || fail "report with its figures"
for f in fig3_entropy_coverage.svg fig4_runtime.svg; do
  head -c 5 "$tmp/r/$f" 2>/dev/null | grep -q "<svg" || fail "report: no $f"
done
[[ "$(sha256sum < "$tmp/r/findings.md")" == "$report_sum" ]] || fail "the figures changed findings.md"
no_leftovers "$tmp/r" "report with its figures"

if [[ $failures -ne 0 ]]; then echo "$failures failure(s)"; exit 1; fi
echo "all reliability (third pass) checks passed"
