#!/usr/bin/env bash
# Installs every build and run dependency of rtsim from Debian 12 packages.
# Run as root (or with sudo). Idempotent: apt-get skips what is already there.
#   bash scripts/install-deps.sh          what building and running need
#   bash scripts/install-deps.sh --test   and what the test suite needs besides (clang-format, black
#                                         and flake8 for the style tests; Slurm and munge for the
#                                         one-node cluster of the Slurm test)
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
PKGS=(
  build-essential cmake ninja-build pkg-config git
  libsystemc-dev libglm-dev libtinygltf-dev libstb-dev
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libfmt-dev
  libtinyobjloader-dev libmeshoptimizer-dev libembree-dev libgtest-dev
  procps python3 python3-numpy python3-matplotlib python3-pil
)
if [ "${1:-}" = "--test" ]; then PKGS+=(clang-format black flake8 slurm-wlm munge); fi
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
