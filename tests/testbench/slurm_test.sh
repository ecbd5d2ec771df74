#!/usr/bin/env bash
# rtsim on a real Slurm cluster (one node, started here by scripts/slurm-local.sh): a sweep emitted
# with --emit slurm is submitted with sbatch, every array task completes, --merge gathers the rows,
# and they equal a local run's; a study's (a reproduction and a sweep) through its study.sh, its
# table equal to a local run's; the same for rtsim animate (robots, when ../shared/scenes is
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

# Waits for every task of job $1 to end; checks each completed with 0 ($2: its output files).
wait_job() {
  local job=$1 out=$2 states
  for _ in $(seq 1 6000); do
    states=$(squeue -h -t all -j "$job" -o %T 2> /dev/null || true)
    if [ -n "$states" ] && ! grep -qvE '^(COMPLETED|FAILED|CANCELLED|TIMEOUT|OUT_OF_MEMORY|NODE_FAIL|PREEMPTED|BOOT_FAIL|DEADLINE)$' <<< "$states"; then
      break
    fi
    sleep 0.5
  done
  local tasks done_ok
  tasks=$(scontrol -o show job "$job" | grep -c 'JobId=')
  done_ok=$(scontrol -o show job "$job" | grep 'JobState=COMPLETED' | grep -c 'ExitCode=0:0')
  echo "job $job: $done_ok of $tasks tasks completed with exit code 0"
  [ "$tasks" -gt 0 ] && [ "$done_ok" -eq "$tasks" ] || {
    scontrol -o show job "$job" >&2
    cat $out >&2 2> /dev/null || true
    fail "job $job did not complete"
  }
}

# Submits DIR/sweep.sbatch and waits for its array.
submit_and_wait() {
  local dir=$1 job
  job=$(RTSIM="$rtsim" sbatch --parsable "$dir/sweep.sbatch")
  job=${job%%;*}
  echo "submitted array job $job ($(grep -o 'array=[0-9-]*' "$dir/sweep.sbatch"))"
  wait_job "$job" "$dir/points/slurm-*.out"
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

# 2. A study: a contention ablation of the city (a reproduction) and the sweep above, as job
# arrays, then the job that gathers them (study.sh submits it after them): its table equals a
# local run's.
cat > "$work/abl.yaml" << YAML
name: slurm-ablation
scenes: [$src/configs/scenes/city.yaml]
hw: $src/configs/hw/ideal.yaml
variants:
  ideal: {}
  all: {hw: $src/configs/hw/tni-paper.yaml}
axes:
  run.lvb: [off, on]
metrics: [frame_ms_all]
YAML
printf '<!-- generated: slurm-study -->\n<!-- end generated: slurm-study -->\n' > "$work/doc.md"
cat > "$work/slurm-study.yaml" << YAML
id: slurm-study
doc: doc.md
runs:
  - dir: abl
    reproduce: ablation
    sweep_file: abl.yaml
    set: [run.width=32, run.height=18]
  - dir: sw
    sweep: sweep.yaml
    plots: false
table:
  renderer: copy_markdown
  file: abl/ablation.md
  from: Sweep
YAML
"$rtsim" study "$work/slurm-study.yaml" --emit slurm --out "$work/study-slurm" > /dev/null
job=$(RTSIM="$rtsim" bash "$work/study-slurm/study.sh")
echo "submitted the study's arrays and its gathering job $job"
wait_job "${job%%;*}" "$work/study-slurm/study-*.out"
"$rtsim" study "$work/slurm-study.yaml" --out "$work/study-local" --jobs 2 > /dev/null
cmp "$work/study-slurm/table.md" "$work/study-local/table.md" ||
  fail "the cluster's study table differs from the local run's"
echo "study: $(grep -c '^|' "$work/study-local/table.md") table lines equal the local run's"

# 3. An animation: two frames of BART's robots
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
