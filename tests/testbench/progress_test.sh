#!/usr/bin/env bash
# The progress line: drawn on a terminal (a pseudo-terminal from `script`), absent otherwise.
# Usage: progress_test.sh RTSIM_BINARY SOURCE_DIR [sanitize]
set -euo pipefail
rtsim=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
# A run long enough for a draw (every 0.5 s): 640x360 takes about 3 s in Release; the sanitizer
# build takes 4 s at 320x180 (10 s at 640x360).
size=(--width 640 --height 360)
[ "${3:-}" = "sanitize" ] && size=(--width 320 --height 180)
args=(run "$src/configs/scenes/city.yaml" --hw "$src/configs/hw/tni-paper.yaml" "${size[@]}" --no-plots)

# Not a terminal: no progress line on stderr.
"$rtsim" "${args[@]}" --out "$work/a" > "$work/a.out" 2> "$work/a.err"
grep -q "phase" "$work/a.err" && fail "progress drawn without a terminal"

# A terminal: at least one progress line, then the summary.
script -qec "$(printf '%q ' "$rtsim" "${args[@]}" --out "$work/b")" /dev/null > "$work/b.tty"
tr '\r' '\n' < "$work/b.tty" | grep -aqE "phase [12] \((primary|shadow)\) [0-9]+%" || fail "no progress line on a terminal"
tr '\r' '\n' < "$work/b.tty" | grep -aq "rays retired" || fail "the progress line lacks rays retired"
grep -aq "LVB on:" "$work/b.tty" || fail "no summary"
# --quiet: nothing, even on a terminal.
script -qec "$(printf '%q ' "$rtsim" "${args[@]}" --out "$work/c" --quiet)" /dev/null > "$work/c.tty"
grep -aq "phase" "$work/c.tty" && fail "progress drawn with --quiet"
echo "progress test passed"
