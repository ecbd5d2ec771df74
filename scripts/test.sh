#!/usr/bin/env bash
# Installs the dependencies, builds rtsim and runs the whole test suite.
#   bash scripts/test.sh              Release build in build/
#   bash scripts/test.sh --sanitize   AddressSanitizer + UBSan build in build-asan/
#   bash scripts/test.sh --tsan       ThreadSanitizer build in build-tsan/ of what runs threads
#                                     (the tests labelled `threads`)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --test
build=build
# A warning fails the build here and in CI (plain builds only warn).
flags=(-DCMAKE_BUILD_TYPE=Release -DRTSIM_WERROR=ON)
select=()
if [ "${1:-}" = "--sanitize" ]; then
  # The brute-force comparisons on the paper's scenes take 100-140 s each under the sanitizers and
  # run the same traversal code as the city one, which stays: the Release pass runs all four.
  # BvhTraversal.HitsJustBeforeAFiniteTmaxAreFound (76 s here, 6 s in Release) is the same kind of
  # test: random rays against brute force, on code BvhTraversal.CityEqualsBruteForceAndTheKdTree
  # runs here. The platform example's kitchen (20 s here) runs the code of its city (1 s).
  # Three command-line tests run rtsim many times over on code shorter ones run here (this pass was
  # 983 s of a 1,840 s CI run on 2026-12-07, these 26-43 s of its tests): a sampled animation
  # (CliSample.* and Cli.AnimateRunsTheFramesAsAResumableSweep stay), a sampled target grown
  # (SampleTarget.NeymanStrata... stays), an ablation (a sweep of plain runs, as other sweeps here).
  select=(-E 'ReferenceTracer\.MatchesBruteForceOn(Bunny|Kitchen|Robots)$|BvhTraversal\.HitsJustBeforeAFiniteTmaxAreFound$|PlatformExample\.TwoFramesOfTheKitchenComeBackWithNoWrongRecord$|SampleAnimate\.EachFrameCarriesItsInterval$|SampleTarget\.AnUnmetTargetIsReportedAndGrowMeetsIt$|Cli\.AblationHasARowPerVariantAndItsIdealAndAllRowsArePlainRuns$')
  build=build-asan
  # -O1 -g1, the sanitizers' usual level: this build was 17 of CI's 36 minutes at -O2 -g (one
  # test file: 26 s at -O2 -g, 14 s at -O1 -g1); reports keep their lines.
  flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
         -DRTSIM_SANITIZE=ON -DRTSIM_BUILD_BENCH=OFF -DRTSIM_WERROR=ON)
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
fi
targets=()
if [ "${1:-}" = "--tsan" ]; then
  # Only the threaded host code: the reference tracer, the LVB preprocessor and a sampled run's
  # functional pass (their unit tests, rtsim render/lvb with threads and a sampled run twice). The
  # simulator itself runs one SystemC thread.
  build=build-tsan
  flags=(-DCMAKE_BUILD_TYPE=Release -DRTSIM_TSAN=ON -DRTSIM_BUILD_BENCH=OFF
         -DRTSIM_BUILD_EXAMPLES=OFF -DRTSIM_WERROR=ON)
  targets=(--target rtsim test_tracer test_lvb test_sampling_shadow)
  select=(-L threads -E 'ReferenceTracer\.MatchesBruteForceOn(Bunny|Kitchen|Robots)$')
  export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1
fi
cmake -S . -B "$build" -G Ninja "${flags[@]}"
cmake --build "$build" -j "$(nproc)" "${targets[@]}"
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" "${select[@]}"
