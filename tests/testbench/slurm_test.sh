#!/usr/bin/env bash
# rtsim on a real Slurm cluster (one node, started here by scripts/slurm-local.sh): a sweep emitted
# with --emit slurm is submitted with sbatch, every array task completes, --merge gathers the rows,
# and they equal a local run's; the same for rtsim animate (robots, when ../shared/scenes is
# there). Where a cluster cannot start (not root, Slurm or munge missing, ports taken) it says why
# and exits 77: ctest reports the test as skipped, never as passed.
# Usage: slurm_test.sh RTSIM_BINARY SOURCE_DIR
set -euo pipefail
rtsim=$(realpath "$1")
src=$(realpath "$2")
work=$(mktemp -d /tmp/rtsim-slurm-test.XXXXXX)
chmod 755 "$work" # the munge user must reach the cluster's folder inside it
cluster="$work/c"
fail() { echo "FAIL: $*" >&2; exit 1; }
cleanup() {
  bash "$src/scripts/slurm-local.sh" stop "$cluster" || echo "FAIL: the cluster did not stop" >&2
  rm -rf "$work"
}
trap cleanup EXIT

set +e
env_line=$(bash "$src/scripts/slurm-local.sh" start "$cluster")
code=$?
set -e
if [ "$code" -eq 77 ]; then
  echo "SKIPPED: no Slurm cluster on this machine (see the line above)"
  exit 77
fi
[ "$code" -eq 0 ] || fail "the cluster did not start (exit $code)"
eval "$env_line"
echo "cluster up: $(sinfo -h -o '%P %D %T %c CPUs')"

# Submits DIR/sweep.sbatch, waits for every array task to end, checks each completed with 0.
submit_and_wait() {
  local dir=$1 job states
  job=$(RTSIM="$rtsim" sbatch --parsable "$dir/sweep.sbatch")
  job=${job%%;*}
  echo "submitted array job $job ($(grep -o 'array=[0-9-]*' "$dir/sweep.sbatch"))"
  for _ in $(seq 1 6000); do
    states=$(squeue -h -t all -j "$job" -o %T 2> /dev/null || true)
    if [ -n "$states" ] && ! grep -qvE '^(COMPLETED|FAILED|CANCELLED|TIMEOUT|OUT_OF_MEMORY|NODE_FAIL|PREEMPTED|BOOT_FAIL|DEADLINE)$' <<< "$states"; then
      break
    fi
    sleep 0.5
  done
  local tasks done_ok
  tasks=$(scontrol -o show job "$job" | grep -c 'ArrayTaskId=')
  done_ok=$(scontrol -o show job "$job" | grep 'JobState=COMPLETED' | grep -c 'ExitCode=0:0')
  echo "array job $job: $done_ok of $tasks tasks completed with exit code 0"
  [ "$tasks" -gt 0 ] && [ "$done_ok" -eq "$tasks" ] || {
    scontrol -o show job "$job" >&2
    cat "$dir"/points/slurm-*.out >&2 2> /dev/null || true
    fail "array job $job did not complete"
  }
}

# 1. A sweep: 4 points of the city, on the cluster and locally
cat > "$work/sweep.yaml" << YAML
name: slurm-sweep
scenes: [$src/configs/scenes/city.yaml]
hw: $src/configs/hw/small.yaml
set: {scene.resolution: [64, 36]}
axes:
  hw.trv.l1.size_kb: [2, 8]
  run.lvb: [on, off]
YAML
"$rtsim" sweep "$work/sweep.yaml" --emit slurm --out "$work/slurm" > /dev/null
submit_and_wait "$work/slurm"
"$rtsim" sweep --merge "$work/slurm" --no-plots | tail -n 1
"$rtsim" sweep "$work/sweep.yaml" --out "$work/local" --jobs 2 --no-plots > /dev/null
cmp "$work/slurm/results.csv" "$work/local/results.csv" ||
  fail "the cluster's merged rows differ from the local run's"
echo "sweep: $(($(wc -l < "$work/local/results.csv") - 1)) merged rows equal the local rows"

# 2. An animation: two frames of BART's robots
robots="${RTSIM_SCENE_ROOT:-$src/../shared/scenes}/bart/robots/Robot.aff"
if [ ! -e "$robots" ]; then
  echo "animate part skipped: no ../shared/scenes (BART robots) on this machine"
  exit 0
fi
animate() {
  "$rtsim" animate "$src/configs/scenes/robots.yaml" --hw "$src/configs/hw/small.yaml" \
    --times 0:1:1 --width 32 --height 18 --lvb both --out "$@"
}
animate "$work/anim-slurm" --emit slurm > /dev/null
submit_and_wait "$work/anim-slurm"
animate "$work/anim-slurm" | tail -n 1 # gathers the frames the tasks ran
animate "$work/anim-local" --jobs 2 > /dev/null
cmp "$work/anim-slurm/frames.csv" "$work/anim-local/frames.csv" ||
  fail "the cluster's frames differ from the local run's"
echo "animate: $(($(wc -l < "$work/anim-local/frames.csv") - 1)) frame rows equal the local rows"
