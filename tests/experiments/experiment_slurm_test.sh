#!/usr/bin/env bash
# canopy experiment on a real SLURM cluster: starts a one-node cluster in a temporary folder
# (tools/slurm/local-cluster.sh: its own munged, free ports), submits a tiny experiment as a
# 2-task job array with tools/slurm/experiment.sbatch, waits for it (bounded), runs canopy
# report and checks that every trial ran exactly once, in the shard its array task owns. The
# cluster is stopped by its pid files whatever happens. Skips (exit 77) only when not root or
# when the SLURM binaries are missing (tools/deps.sh installs them, so CI runs it).
set -euo pipefail
canopy="$1"
src=$(pwd)
if [[ $(id -u) -ne 0 ]]; then echo "SKIP: the SLURM test needs root (slurmd, munged as munge)"; exit 77; fi
for b in slurmctld slurmd munged sbatch squeue; do
  command -v "$b" >/dev/null || { echo "SKIP: $b missing (tools/deps.sh installs slurm-wlm and munge)"; exit 77; }
done
dir=$(mktemp -d /tmp/canopy-slurm-test.XXXXXX)
chmod 755 "$dir"  # munged runs as the munge user inside it
cleanup() {
  "$src/tools/slurm/local-cluster.sh" stop "$dir/cluster" >/dev/null 2>&1 || true
  rm -rf "$dir"
}
trap cleanup EXIT
fail() { echo "slurm test: $*"; for f in "$dir"/job/slurm-*.out "$dir"/cluster/log/*.log; do [[ -f $f ]] && { echo "== $f"; tail -20 "$f"; }; done; exit 1; }

eval "$("$src/tools/slurm/local-cluster.sh" start "$dir/cluster")"
[[ -n ${SLURM_CONF:-} ]] || fail "the cluster did not start"

cat > "$dir/tiny.yaml" <<YAML
name: slurm-tiny
world: $src/worlds/small.yaml
overrides:
  mission: {loop: {views_per_stop: 1}, scan: {heights_m: [0.85], azimuths_deg: [0.0], extra_heights_m: [0.55]}}
methods:
  - {label: ours, method: ours}
  - {label: predefined, method: predefined}
p_gt: [1.0]
seeds: [1, 2]
trial_timeout_s: 120
YAML
# Submitted from a folder of its own, as on a cluster (slurm-*.out land there); the binary by CANOPY.
mkdir -p "$dir/job"
cd "$dir/job"
job=$(CANOPY="$canopy" sbatch --parsable --array=0-1 --cpus-per-task=1 --export=ALL \
      "$src/tools/slurm/experiment.sbatch" "$dir/tiny.yaml" "$dir/out") || fail "sbatch failed"
job=${job%%;*}
echo "slurm test: submitted array job $job"
for _ in $(seq 1 240); do
  [[ -z $(squeue -h -j "$job" 2>/dev/null) ]] && break
  sleep 0.5
done
[[ -z $(squeue -h -j "$job" 2>/dev/null) ]] && done_ok=1 || done_ok=0
(( done_ok )) || fail "the array did not finish within 120 s"
cd "$src"
for t in 0 1; do [[ -f "$dir/job/slurm-${job}_$t.out" ]] || fail "no output of array task $t"; done

"$canopy" report "$dir/out" --no-plots 2>/dev/null || fail "canopy report failed"
grep -q "4 expected, 4 ok, 0 failed, 0 missing" "$dir/out/report/findings.md" || fail "findings: $(head -3 "$dir/out/report/findings.md")"
python3 - "$dir" "$job" <<'PY' || fail "trial check failed"
import json, pathlib, re, sys
d, job = pathlib.Path(sys.argv[1]), sys.argv[2]
exp = json.load(open(d / "out" / "experiment.json"))
ids = [t["id"] for t in exp["trials"]]
assert len(ids) == 4, ids
logs = {t: (d / "job" / f"slurm-{job}_{t}.out").read_text() for t in (0, 1)}
for k, i in enumerate(ids):
    runs = {t: len(re.findall(rf"trial {re.escape(i)}: started", logs[t])) for t in (0, 1)}
    assert sum(runs.values()) == 1, (i, runs)          # ran exactly once over the array
    assert runs[k % 2] == 1, (i, runs)                  # by the task owning its shard
    rec = json.load(open(d / "out" / "trials" / i / "trial.json"))
    assert rec["status"] == "ok" and rec["shard"] == f"{k % 2}/2", rec["shard"]
    assert f"SLURM job" in rec["runner"] and f"array task {k % 2}" in rec["runner"], rec["runner"]
assert not [p for p in (d / "out" / "trials").iterdir() if p.name.endswith(".partial")]
print("slurm test: ok (4 trials, each once, by its shard's array task)")
PY
