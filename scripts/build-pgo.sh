#!/usr/bin/env bash
# A profile-guided build of the rtsim command (GCC's -fprofile-generate, then -fprofile-use): the
# same code and the same figures to the last bit (bench/same_figures.py), a few percent fewer
# instructions but no host time measurably saved on top of the model's -O3
# (docs/changes.md, issue 20). Takes about twice a plain build plus a minute of training.
#   bash scripts/build-pgo.sh [BUILD_DIR]      (default build-pgo; the binary is BUILD_DIR/rtsim)
# The training runs the procedural city and, when the scene root holds them (RTSIM_SCENE_ROOT,
# see configs/README.md), the paper's three scenes, small frames on the paper's hardware.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-pgo}
common=(-G Ninja -DCMAKE_BUILD_TYPE=Release -DRTSIM_BUILD_TESTS=OFF -DRTSIM_BUILD_BENCH=OFF
        -DRTSIM_BUILD_EXAMPLES=OFF)
train=$(mktemp -d)
trap 'rm -rf "$train"' EXIT

# Stage 1: an instrumented binary (a profile of an earlier build would be stale).
if [ -d "$build" ]; then find "$build" -name '*.gcda' -delete; fi
cmake -S . -B "$build" "${common[@]}" -DRTSIM_PGO=generate
cmake --build "$build" -j "$(nproc)" --target rtsim

# Stage 2: the training, culling on and off, both memory systems.
run() { "$build/rtsim" run "$@" --out "$train/run" --quiet --no-plots > /dev/null; rm -rf "$train/run"; }
run configs/scenes/city.yaml --hw configs/hw/tni-paper.yaml --width 320 --height 180
run configs/scenes/city.yaml --hw configs/hw/tni-paper.yaml --width 160 --height 90 --lvb off
run configs/scenes/city.yaml --hw configs/hw/small.yaml --width 160 --height 90
for scene in robots kitchen bunny; do
  if "$build/rtsim" info "configs/scenes/$scene.yaml" > /dev/null 2>&1; then
    run "configs/scenes/$scene.yaml" --hw configs/hw/tni-paper.yaml --width 160 --height 90
  else
    echo "build-pgo: $scene not found under the scene root, not trained on"
  fi
done

# Stage 3: the same directory (the profile lies beside each object), compiled with the profile.
cmake -S . -B "$build" "${common[@]}" -DRTSIM_PGO=use
cmake --build "$build" -j "$(nproc)" --target rtsim
echo "build-pgo: $build/rtsim"
