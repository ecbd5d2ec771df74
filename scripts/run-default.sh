#!/usr/bin/env bash
# Installs the dependencies, builds rtsim and runs the default job: the procedural city.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# The test command's flags (scripts/test.sh): with the same flags it reuses every object built here
# instead of compiling them again with -Werror added.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DRTSIM_WERROR=ON
# Only what the job runs; scripts/test.sh builds the rest (tests, benchmarks, examples).
cmake --build build -j "$(nproc)" --target rtsim
./build/rtsim info configs/scenes/city.yaml
./build/rtsim render configs/scenes/city.yaml --out out/city
./build/rtsim run configs/scenes/city.yaml --hw configs/hw/tni-paper.yaml --out out/city-model --check
