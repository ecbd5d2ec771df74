#!/bin/bash
# Instructions the simulation executes (callgrind, the simulation alone: from sc_start, which no
# build inlines), a measure of the model's host cost that a shared, noisy machine does not disturb
# (issue 20).
#   bash bench/instructions.sh BIN [SCENE.yaml] [WIDTH HEIGHT]
# Default: robots at 160x90 on tni-paper.yaml (about 3 minutes under valgrind). Prints the total.
set -euo pipefail
bin=$1
scene=${2:-configs/scenes/robots.yaml}
width=${3:-160}
height=${4:-90}
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
valgrind --tool=callgrind --collect-atstart=no --toggle-collect='sc_core::sc_start()' \
  --callgrind-out-file="$tmp/callgrind.out" "$bin" run "$src/$scene" --hw "$src/configs/hw/tni-paper.yaml" \
  --width "$width" --height "$height" --out "$tmp/run" --quiet --no-plots > /dev/null 2>&1
callgrind_annotate "$tmp/callgrind.out" 2>/dev/null | awk '/PROGRAM TOTALS/ {print $1, "instructions"}'
