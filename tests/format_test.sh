#!/usr/bin/env bash
# Every C++ file of ours is as clang-format (.clang-format: Google, 100 columns) writes it. Fails
# naming the files that are not; `clang-format -i FILE` fixes one.
# Usage: format_test.sh SOURCE_DIR
set -euo pipefail
cd "$1"
command -v clang-format > /dev/null || { echo "FAIL: clang-format is not installed (bash scripts/install-deps.sh --test)"; exit 1; }
mapfile -t files < <(find . \( -path './build*' -o -path './.git' -o -path './out' \) -prune -o \
                       -type f \( -name '*.h' -o -name '*.cpp' \) -print | sort)
clang-format --dry-run --Werror "${files[@]}"
echo "format: ${#files[@]} files ok"
