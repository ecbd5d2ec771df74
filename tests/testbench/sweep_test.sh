#!/usr/bin/env bash
# rtsim sweep end to end: 8 points with --jobs 2, one job killed midway, the rerun runs only the
# missing point; the sweep killed at random moments and rerun until done gives the same results;
# a Slurm array task run by hand gives the same row as the local run; --merge.
# Usage: sweep_test.sh RTSIM_BINARY SOURCE_DIR [sanitize]
# (With "sanitize", a sanitizer build: the random-kill part, a test of the sweep engine's logic that
# the Release pass runs, is left out; there it takes minutes.)
set -euo pipefail
rtsim=$1
src=$2
sanitize=${3:-}
work=$(mktemp -d)
fail() { echo "FAIL: $*" >&2; exit 1; }

cp "$src/configs/hw/tni-paper.yaml" "$work/hw.yaml"
cat > "$work/sweep.yaml" <<YAML
name: test-sweep
scenes: [$src/configs/scenes/city.yaml]
hw: $work/hw.yaml
set: {scene.resolution: [200, 112]}
axes:
  hw.trv.l1.size_kb: [4, 8, 16, 32]
  run.lvb: [on, off]
YAML

sweep_pid=""
trap '[ -n "$sweep_pid" ] && kill "$sweep_pid" 2>/dev/null; rm -rf "$work"' EXIT

# Once a first point has finished, the pid of a point process whose row is not written yet.
running_point() {
  local dir=$1 pid point
  compgen -G "$dir/points/*/row.json" > /dev/null || return 1
  for pid in $(pgrep -P "$sweep_pid"); do
    point=$(tr '\0' ' ' < "/proc/$pid/cmdline" 2>/dev/null | sed -n 's/.*--point \([0-9]*\).*/\1/p')
    [ -n "$point" ] || continue
    [ -e "$dir/points/$(printf 'p%04d' "$point")/row.json" ] && continue
    echo "$pid"
    return 0
  done
  return 1
}
# Returns 1 when the sweep ends first (on a fast machine every point may finish before one is
# seen), 2 when none is seen running within 60 s.
wait_for_running_point() {
  local victim=""
  for _ in $(seq 1 6000); do
    victim=$(running_point "$1") && break
    kill -0 "$sweep_pid" 2> /dev/null || return 1
    sleep 0.01
  done
  [ -n "$victim" ] || return 2
  echo "$victim"
}
rows_of() { ls "$1"/points/*/row.json 2> /dev/null | wc -l; }

# 1. Kill one running point's process midway; the sweep finishes the others and reports it.
"$rtsim" sweep "$work/sweep.yaml" --out "$work/a" --jobs 2 --no-plots > "$work/first.log" 2>&1 &
sweep_pid=$!
# The point chosen may write its row and exit in the instant before the kill (CI at 402dd1e:
# 'kill: No such process'): then the next running one, until the sweep has none left.
for _ in $(seq 1 50); do
  found=0
  victim=$(wait_for_running_point "$work/a") || found=$?
  [ "$found" -ne 2 ] || fail "no running point seen in 60 s"
  [ "$found" -eq 0 ] || break  # the sweep ended first
  kill -KILL "$victim" 2> /dev/null && break
done
set +e
wait "$sweep_pid"
code=$?
set -e
cat "$work/first.log"
done_first=$(rows_of "$work/a")
if grep -q "FAILED (killed by signal 9" "$work/first.log"; then
  [ "$code" -eq 1 ] || fail "the sweep with a killed point exited with $code, expected 1"
  [ "$done_first" -eq 7 ] || fail "$done_first rows after the first run, expected 7"
else
  # The point wrote its row in the instant before the kill: nothing to resume from this part.
  [ "$done_first" -eq 8 ] || fail "no point reported killed, yet $done_first rows"
fi

# 2. The rerun runs only the missing point(s).
"$rtsim" sweep "$work/sweep.yaml" --out "$work/a" --jobs 2 --no-plots > "$work/second.log" 2>&1 || fail "rerun failed"
cat "$work/second.log"
grep -q "8 points, $done_first already done, running $((8 - done_first)) with 2 jobs" "$work/second.log" ||
  fail "the rerun did not run just the missing points"
rows=$(($(wc -l < "$work/a/results.csv") - 1))
[ "$rows" -eq 8 ] || fail "results.csv has $rows rows, expected 8"

# 2b. Kill the sweep itself midway: its points die with it, the rerun runs the rest.
"$rtsim" sweep "$work/sweep.yaml" --out "$work/c" --jobs 2 --no-plots > /dev/null 2>&1 &
sweep_pid=$!
wait_for_running_point "$work/c" > /dev/null ||
  fail "no running point seen (the sweep ended first, or none ran within 60 s)"
kill -KILL "$sweep_pid" 2> /dev/null || fail "the sweep ended before it could be killed"
wait "$sweep_pid" 2> /dev/null || true
sweep_pid=""
sleep 0.5  # the points get SIGTERM when their parent dies
pgrep -f "sweep --out $work/c --point" > /dev/null && fail "point processes outlived the sweep"
done_c=$(rows_of "$work/c")
[ "$done_c" -lt 8 ] || fail "every point finished before the kill"
"$rtsim" sweep "$work/sweep.yaml" --out "$work/c" --jobs 2 --no-plots > "$work/c.log" 2>&1 || fail "rerun after a killed sweep failed"
grep -q "8 points, $done_c already done, running $((8 - done_c)) with 2 jobs" "$work/c.log" || fail "rerun after a killed sweep"
[ "$(rows_of "$work/c")" -eq 8 ] || fail "rows after the rerun"
cmp "$work/a/results.csv" "$work/c/results.csv" || fail "the same sweep gave different results"

# 2c. Killed at random moments (SIGKILL), rerun each time until it finishes: the results are an
# uninterrupted run's, and no kill leaves the directory locked or a point half-recorded.
if [ -z "$sanitize" ]; then
  # The kills' moments scale with an uninterrupted sweep's time here, so the first lands inside a
  # run on a fast machine as on a slow one (a fixed 0-3 s let a fast machine finish first).
  start_ns=$(date +%s%N)
  "$rtsim" sweep "$work/sweep.yaml" --out "$work/t" --jobs 2 --no-plots > /dev/null 2>&1 || fail "the timing sweep failed"
  full_ms=$((($(date +%s%N) - start_ns) / 1000000))
  cmp "$work/a/results.csv" "$work/t/results.csv" || fail "an uninterrupted sweep gave other results"
  RANDOM=22
  kills=0
  for attempt in $(seq 1 40); do
    "$rtsim" sweep "$work/sweep.yaml" --out "$work/d" --jobs 2 --no-plots > "$work/d.log" 2>&1 &
    sweep_pid=$!
    # Within the first half of a whole sweep's time, later as the attempts go on (each resumes the
    # last, and from the ninth on it has a whole sweep's time).
    wait_ms=$((RANDOM % (full_ms / 2 + 1) + (attempt - 1) * full_ms / 8))
    sleep "$(printf '%d.%03d' $((wait_ms / 1000)) $((wait_ms % 1000)))"
    if kill -KILL "$sweep_pid" 2> /dev/null; then kills=$((kills + 1)); fi
    set +e
    wait "$sweep_pid" 2> /dev/null
    code=$?
    set -e
    sweep_pid=""
    [ "$code" -eq 0 ] && break
    grep -q "another sweep is running" "$work/d.log" && fail "a killed sweep left its directory locked"
    sleep 0.2  # its points get SIGTERM from the kernel when it dies
  done
  [ "$code" -eq 0 ] || fail "the sweep never finished in 40 attempts"
  [ "$kills" -gt 0 ] || fail "no attempt was killed"
  cmp "$work/a/results.csv" "$work/d/results.csv" || fail "a sweep killed $kills times gave other results"
  echo "killed $kills times, then finished with the uninterrupted run's results"
fi

# 3. The same sweep for Slurm: the script parses, one array task by hand gives the local row.
"$rtsim" sweep "$work/sweep.yaml" --out "$work/b" --emit slurm > /dev/null
bash -n "$work/b/sweep.sbatch" || fail "sweep.sbatch does not parse"
grep -q "^#SBATCH --array=0-7$" "$work/b/sweep.sbatch" || fail "array range"
SLURM_ARRAY_TASK_ID=5 bash "$work/b/sweep.sbatch" > /dev/null
cmp "$work/a/points/p0005/row.json" "$work/b/points/p0005/row.json" || fail "the array task's row differs from the local one"
# --merge of b into LOG; its exit code in $code.
merge_b() {
  set +e
  "$rtsim" sweep --merge "$work/b" --no-plots > "$1" 2>&1
  code=$?
  set -e
}
merge_b "$work/merge.log"
[ "$code" -eq 1 ] || fail "merge with 7 missing points exited with $code, expected 1"
grep -q "merged 1 of 8 points" "$work/merge.log" || fail "merge count"
[ "$(($(wc -l < "$work/b/results.csv") - 1))" -eq 1 ] || fail "merged results.csv should have 1 row"
# A damaged row is named (and run again by the next sweep), not skipped in silence.
echo '{"id": ' > "$work/b/points/p0005/row.json"
merge_b "$work/merge2.log"
[ "$code" -eq 1 ] || fail "merge with a damaged row exited with $code, expected 1"
grep -q "merged 0 of 8 points" "$work/merge2.log" || fail "merge count with a damaged row"
grep -q "p0005 (.*not valid JSON" "$work/merge2.log" || fail "the damaged row is not named"
grep -q "an unreadable row" "$work/b/results.json" || fail "results.json does not list the damaged row"

# 4. A directory holding another sweep is refused: other points, or an input file that changed.
refused() {
  set +e
  "$rtsim" sweep "$work/sweep.yaml" --out "$work/a" --no-plots > /dev/null 2> "$work/other.err"
  local code=$?
  set -e
  [ "$code" -eq 2 ] || fail "$1: exited with $code, expected 2"
  grep -q "another sweep" "$work/other.err" || fail "$1: message"
}
echo "# edited" >> "$work/hw.yaml"
refused "a changed hardware file"
sed -i 's/\[4, 8, 16, 32\]/[2, 4]/' "$work/sweep.yaml"
refused "other points"
echo "sweep test passed"
