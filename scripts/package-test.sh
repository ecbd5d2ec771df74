#!/usr/bin/env bash
# The package as another project sees it (docs/systemc-integration.md, "The package"):
#   bash scripts/package-test.sh BUILD_DIR          cmake --install into a temporary prefix, then
#                                                   every example configured, built and run from
#                                                   the installed copy with find_package(rtsim)
#   bash scripts/package-test.sh BUILD_DIR --deb    also: cpack -G DEB, dpkg -i (root), the same
#                                                   against /usr, dpkg -r
# Nothing of the source tree is used after the install.
set -euo pipefail
build=$(cd "$1" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# One smoke run per example (name, build dir, install prefix): its arguments and what its
# output must contain.
smoke() {
  case "$1" in
    tlm_memory) "$2/tlm_memory_example" triangle 0 100 | grep -q '"cycles":677' ;;
    # the hardware file from the installed configs (share/rtsim/configs), two right frames
    platform)
      local out
      out=$("$2/platform_example" city 64 36)
      grep -qF "\"hw\":\"$3/share/rtsim/configs/hw/tni-paper.yaml\"" <<< "$out" &&
        [ "$(grep -c '"wrong_records":0' <<< "$out")" = 2 ] ;;
    *) echo "package-test: no smoke run for example $1" >&2; return 1 ;;
  esac
}

# Configure, build and run every example under $1/share/rtsim/examples against prefix $2.
build_examples() {
  local examples=$1/share/rtsim/examples prefix=$2 tag=$3
  for dir in "$examples"/*/; do
    local name
    name=$(basename "$dir")
    cp -r "$dir" "$work/src-$tag-$name"
    cmake -S "$work/src-$tag-$name" -B "$work/build-$tag-$name" -G Ninja \
      -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release > "$work/cmake-$tag-$name.log"
    cmake --build "$work/build-$tag-$name" > "$work/make-$tag-$name.log"
    smoke "$name" "$work/build-$tag-$name" "$prefix" 2> /dev/null
    echo "package-test: $name built and ran against $prefix ($tag)"
  done
}

cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
build_examples "$work/prefix" "$work/prefix" prefix

if [ "${2:-}" = "--deb" ]; then
  (cd "$build" && cpack -G DEB > "$work/cpack.log")
  deb=$(ls "$build"/rtsim-dev_*.deb)
  dpkg -i "$deb" > /dev/null
  trap 'dpkg -r rtsim-dev > /dev/null; rm -rf "$work"' EXIT
  build_examples /usr /usr deb
fi
