#!/usr/bin/env bash
# The host code that runs threads (the reference tracer, the LVB preprocessor and its --verify
# tracing, a sampled run's functional pass): rtsim render and rtsim lvb with 4 threads write what
# one thread writes, host timings and thread counts aside; a sampled run writes the same report
# twice. Under ThreadSanitizer (scripts/test.sh --tsan) a data race ends the
# run with TSan's exit code, which fails the test.
# Usage: threads_test.sh RTSIM_BINARY SOURCE_DIR
set -euo pipefail
rtsim=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# A JSON report without what depends on the host: seconds and thread counts.
same_json() {
  python3 - "$1" "$2" << 'PY'
import json, sys
def strip(j):
    if isinstance(j, dict):
        return {k: strip(v) for k, v in j.items()
                if not any(w in k for w in ("seconds", "threads")) and k != "host"}
    if isinstance(j, list):
        return [strip(v) for v in j]
    return j
a, b = (strip(json.load(open(p))) for p in sys.argv[1:3])
sys.exit(0 if a == b else 1)
PY
}

scene="$src/configs/scenes/city.yaml"
# The paper's all-pairs preprocessing on a smaller city (under ThreadSanitizer the default city's
# takes a minute per run)
printf 'name: city-small\ngeometry:\n  - procedural: {kind: city, blocks: 5, seed: 1, sphere_segments: 12, lights: 4}\n' > "$work/small.yaml"
for t in 1 4; do
  "$rtsim" render "$scene" --width 96 --height 54 --reflections 1 --threads "$t" \
    --out "$work/render$t" > /dev/null || fail "render with $t threads"
  "$rtsim" lvb "$scene" --width 96 --height 54 --verify --threads "$t" --lvb-threads "$t" \
    --out "$work/lvb$t" > /dev/null || fail "lvb with $t threads"
  "$rtsim" lvb "$work/small.yaml" --width 96 --height 54 --method paper --lvb-threads "$t" \
    --out "$work/paper$t" > /dev/null || fail "lvb --method paper with $t threads"
done
for f in render.png mask.npy visibility.npy; do
  cmp "$work/render1/$f" "$work/render4/$f" || fail "render: $f differs with 4 threads"
done
same_json "$work/render1/render.json" "$work/render4/render.json" ||
  fail "render.json differs with 4 threads"
for d in lvb paper; do
  for f in culled.npy mask.npy; do
    cmp "$work/${d}1/$f" "$work/${d}4/$f" || fail "$d: $f differs with 4 threads"
  done
  same_json "$work/${d}1/lvb.json" "$work/${d}4/lvb.json" || fail "$d: lvb.json differs with 4 threads"
done
# A sampled run's functional pass runs on a thread beside the simulation (testbench/
# run_command.cpp): twice, the same report and sample.csv.
for k in 1 2; do
  "$rtsim" run "$scene" --hw "$src/configs/hw/tni-paper.yaml" --width 128 --height 72 \
    --sample 0.2 --set run.sample_unit=512 --set run.sample_warmup=512 --no-plots --quiet \
    --out "$work/sampled$k" > /dev/null || fail "sampled run $k"
done
same_json "$work/sampled1/report.json" "$work/sampled2/report.json" ||
  fail "a sampled run's report.json differs from run to run"
cmp "$work/sampled1/sample.csv" "$work/sampled2/sample.csv" || fail "sample.csv differs"
# Strata in issue order: no walk steps before the simulation.
"$rtsim" run "$scene" --hw "$src/configs/hw/tni-paper.yaml" --width 128 --height 72 \
  --sample 0.2 --set run.sample_unit=512 --set run.sample_warmup=512 \
  --set run.sample_strata=issue --no-plots --quiet --out "$work/issue" > /dev/null ||
  fail "sampled run with strata in issue order"
echo "render, lvb (hierarchical, --verify) and lvb (paper): 4 threads give one thread's outputs;"
echo "a sampled run with its functional pass beside the simulation: the same report twice"
