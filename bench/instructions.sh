#!/bin/bash
# Instructions the simulation executes (callgrind, the simulation alone: from sc_start, which no
# build inlines), a measure of the model's host cost that a shared, noisy machine does not disturb
# (issue 20).
#   bash bench/instructions.sh [--cache-sim] BIN [SCENE.yaml] [WIDTH HEIGHT]
# Default: robots at 160x90 on tni-paper.yaml (about 3 minutes under valgrind). Prints the total.
# --cache-sim also simulates a host cache like this machine's (a 32 KB, 8-way L1 data cache and
# a 1 MB, 16-way L2 as the last level) and prints the L1 and last-level data misses: what the
# instruction count does not see (about 6 minutes).
set -euo pipefail
cache_sim=()
if [ "${1:-}" = "--cache-sim" ]; then
  cache_sim=(--cache-sim=yes --D1=32768,8,64 --LL=1048576,16,64)
  shift
fi
bin=$1
scene=${2:-configs/scenes/robots.yaml}
width=${3:-160}
height=${4:-90}
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
valgrind --tool=callgrind "${cache_sim[@]}" --collect-atstart=no --toggle-collect='sc_core::sc_start()' \
  --callgrind-out-file="$tmp/callgrind.out" "$bin" run "$src/$scene" --hw "$src/configs/hw/tni-paper.yaml" \
  --width "$width" --height "$height" --out "$tmp/run" --quiet --no-plots > /dev/null 2>&1
# The totals line lists the events in the order of the "Events shown" line.
callgrind_annotate "$tmp/callgrind.out" 2>/dev/null | awk '
  /^Events shown:/ { for (i = 3; i <= NF; ++i) name[i - 2] = $i }
  /PROGRAM TOTALS/ {
    k = 0
    for (i = 1; i <= NF; ++i) if ($i ~ /^[0-9,]+$/) value[++k] = $i
    for (j = 1; j <= k; ++j) {
      if (name[j] == "Ir") print value[j], "instructions"
      if (name[j] == "D1mr") print value[j], "L1 data read misses"
      if (name[j] == "D1mw") print value[j], "L1 data write misses"
      if (name[j] == "DLmr") print value[j], "last-level data read misses"
      if (name[j] == "DLmw") print value[j], "last-level data write misses"
    }
  }'
