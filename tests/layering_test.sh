#!/usr/bin/env bash
# The host folders lean one way (docs/architecture.md): a file may not include, and a folder's
# CMakeLists.txt may not link, a folder its rule forbids; inside model/, a layer may not include a
# layer above it. Fails naming every file and line that does.
# Usage: layering_test.sh SOURCE_DIR
set -euo pipefail
src=$1
cd "$src"

# Project folders: the source tree's top-level folders (an include "X/..." of any other X is a
# system or third-party header).
folders=$(find . -mindepth 1 -maxdepth 1 -type d ! -name '.*' ! -name 'build*' -printf '%f\n' | sort)
# The library each folder's CMakeLists.txt builds.
declare -A library=([scene]=rtsim_scene_types [scene_loader]=rtsim_scene [kernels]=rtsim_kernels
                    [model]=rtsim_model [config_loader]=rtsim_config
                    [testbench]=rtsim_cli)

# What a folder may not include: the whole project but common/ and scene/ for the two data folders.
forbidden() {
  case $1 in
    common | scene) grep -vxE 'common|scene' <<< "$folders" ;;
    scene_loader) echo kernels model config_loader testbench ;;
    kernels) echo scene_loader model config_loader testbench ;;
    model) echo scene_loader config_loader testbench ;;
    config_loader) echo testbench ;;
  esac
}

status=0
violation() {
  echo "FAIL: $1: $2"
  status=1
}
for dir in common scene scene_loader kernels model config_loader; do
  [ -d "$dir" ] || continue
  for bad in $(forbidden "$dir"); do
    while IFS= read -r hit; do
      violation "$hit" "$dir/ may not include $bad/"
    done < <(grep -rnE --include='*.h' --include='*.hpp' --include='*.cpp' \
               "^[[:space:]]*#[[:space:]]*include[[:space:]]*[\"<]$bad/" "$dir")
    lib=${library[$bad]:-}
    [ -n "$lib" ] && [ -f "$dir/CMakeLists.txt" ] || continue
    while IFS= read -r hit; do
      violation "$dir/CMakeLists.txt:$hit" "$dir/ may not link $lib, the library of $bad/"
    done < <(grep -nw "$lib" "$dir/CMakeLists.txt")
  done
done
# Inside model/, the layers lean one way too: sim/ (calendar, FIFOs, statistics, tracing) below
# memory/ (L1 to DRAM, the TLM-2.0 boundary) below units/ (the ray-processing blocks) below the
# accelerator (model/accelerator*: the netlist and its configuration; beside it its functional mode,
# model/functional/), which alone see them all.
# device/ (the register block and the host's driver) sees sim/ only: it is the face a platform
# programs, beside the blocks, not above them.
model_forbidden() {
  case $1 in
    sim) echo "model/memory/ model/units/ model/device/ model/accelerator model/functional/" ;;
    memory) echo "model/units/ model/device/ model/accelerator model/functional/" ;;
    units) echo "model/device/ model/accelerator model/functional/" ;;
    device) echo "model/memory/ model/units/ model/accelerator model/functional/" ;;
  esac
}
for layer in sim memory units device; do
  [ -d "model/$layer" ] || continue
  for bad in $(model_forbidden "$layer"); do
    while IFS= read -r hit; do
      violation "$hit" "model/$layer/ may not include $bad"
    done < <(grep -rnE --include='*.h' --include='*.hpp' --include='*.cpp' \
               "^[[:space:]]*#[[:space:]]*include[[:space:]]*[\"<]$bad" "model/$layer")
  done
done
# Every model file lives in a layer or is the accelerator (model/accelerator* and, beside it, its
# functional mode, model/functional/, and its pricing, model/energy/).
while IFS= read -r stray; do
  violation "$stray" "a model file outside model/{sim,memory,units,device,functional,energy}/ that is not the accelerator"
done < <(find model -maxdepth 1 -type f \( -name '*.h' -o -name '*.cpp' \) ! -name 'accelerator*')
while IFS= read -r stray; do
  violation "$stray" "a model folder that is not a layer (sim, memory, units, device), functional/ or energy/"
done < <(find model -mindepth 1 -maxdepth 1 -type d ! -name sim ! -name memory ! -name units \
           ! -name device ! -name functional ! -name energy)
# testbench/ leans one way too, by concern: sampling/ (the sample's statistics) below run/ (one
# run, full or sampled) below studies/ (sweeps, reproductions, studies: many runs) below the
# commands at its top level (main.cpp, commands.h and the commands of one scene: render, info, lvb).
testbench_forbidden() {
  case $1 in
    sampling) echo "testbench/run/ testbench/studies/ testbench/[a-z_]*\.h" ;;
    run) echo "testbench/studies/ testbench/[a-z_]*\.h" ;;
    studies) echo "testbench/[a-z_]*\.h" ;;
  esac
}
for concern in sampling run studies; do
  [ -d "testbench/$concern" ] || continue
  for bad in $(testbench_forbidden "$concern"); do
    while IFS= read -r hit; do
      violation "$hit" "testbench/$concern/ may not include $bad"
    done < <(grep -rnE --include='*.h' --include='*.cpp' \
               "^[[:space:]]*#[[:space:]]*include[[:space:]]*[\"<]$bad" "testbench/$concern")
  done
done
while IFS= read -r stray; do
  violation "$stray" "a testbench folder that is not a concern (sampling, run, studies)"
done < <(find testbench -mindepth 1 -maxdepth 1 -type d ! -name sampling ! -name run ! -name studies)
[ $status -eq 0 ] && echo "layering: ok"
exit $status
