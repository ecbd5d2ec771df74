#!/usr/bin/env bash
# rtsim sweep end to end: 8 points with --jobs 2, one job killed midway, the rerun runs only the
# missing point; a Slurm array task run by hand gives the same row as the local run; --merge.
# Usage: sweep_test.sh RTSIM_BINARY SOURCE_DIR
set -euo pipefail
rtsim=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

cat > "$work/sweep.yaml" <<YAML
name: test-sweep
scenes: [$src/configs/scenes/city.yaml]
hw: $src/configs/hw/tni-paper.yaml
set: {scene.resolution: [200, 112]}
axes:
  hw.trv.l1.size_kb: [4, 8, 16, 32]
  run.lvb: [on, off]
YAML

# 1. Kill one running point's process; the sweep goes on and reports it.
"$rtsim" sweep "$work/sweep.yaml" --out "$work/a" --jobs 2 --no-plots > "$work/first.log" 2>&1 &
sweep_pid=$!
# Midway: once a first point has finished, kill a point that is running.
victim=""
for _ in $(seq 1 1000); do
  if compgen -G "$work/a/points/*/row.json" > /dev/null; then
    victim=$(pgrep -n -P "$sweep_pid" || true)  # the newest: far from finishing
    [ -n "$victim" ] && break
  fi
  sleep 0.01
done
[ -n "$victim" ] || fail "no point process seen"
kill -KILL "$victim"
set +e
wait "$sweep_pid"
code=$?
set -e
cat "$work/first.log"
[ "$code" -eq 1 ] || fail "the sweep with a killed point exited with $code, expected 1"
grep -q "FAILED (killed by signal 9" "$work/first.log" || fail "the killed point is not reported"
done_first=$(ls "$work"/a/points/*/row.json | wc -l)
[ "$done_first" -eq 7 ] || fail "$done_first rows after the first run, expected 7"

# 2. The rerun runs only the missing point.
"$rtsim" sweep "$work/sweep.yaml" --out "$work/a" --jobs 2 --no-plots > "$work/second.log" 2>&1 || fail "rerun failed"
cat "$work/second.log"
grep -q "8 points, 7 already done, running 1 with 2 jobs" "$work/second.log" || fail "the rerun did not run just the missing point"
rows=$(($(wc -l < "$work/a/results.csv") - 1))
[ "$rows" -eq 8 ] || fail "results.csv has $rows rows, expected 8"

# 3. The same sweep for Slurm: the script parses, one array task by hand gives the local row.
"$rtsim" sweep "$work/sweep.yaml" --out "$work/b" --emit slurm > /dev/null
bash -n "$work/b/sweep.sbatch" || fail "sweep.sbatch does not parse"
grep -q "^#SBATCH --array=0-7$" "$work/b/sweep.sbatch" || fail "array range"
SLURM_ARRAY_TASK_ID=5 bash "$work/b/sweep.sbatch" > /dev/null
cmp "$work/a/points/p0005/row.json" "$work/b/points/p0005/row.json" || fail "the array task's row differs from the local one"
set +e
"$rtsim" sweep --merge "$work/b" --no-plots > "$work/merge.log" 2>&1
code=$?
set -e
[ "$code" -eq 1 ] || fail "merge with 7 missing points exited with $code, expected 1"
grep -q "merged 1 of 8 points" "$work/merge.log" || fail "merge count"
[ "$(($(wc -l < "$work/b/results.csv") - 1))" -eq 1 ] || fail "merged results.csv should have 1 row"

# 4. A directory holding another sweep is refused.
sed -i 's/\[4, 8, 16, 32\]/[2, 4]/' "$work/sweep.yaml"
set +e
"$rtsim" sweep "$work/sweep.yaml" --out "$work/a" --no-plots > /dev/null 2> "$work/other.err"
code=$?
set -e
[ "$code" -eq 2 ] || fail "another sweep in the same directory exited with $code, expected 2"
grep -q "another sweep" "$work/other.err" || fail "message for another sweep"
echo "sweep test passed"
