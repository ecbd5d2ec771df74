#!/usr/bin/env bash
# Every Python file of ours is as black writes it and flake8-clean, both at 100 columns
# (pyproject.toml, .flake8). Fails naming the files and lines that are not; `black FILE` fixes the
# layout, flake8's findings are fixed by hand.
# Usage: python_style_test.sh SOURCE_DIR
set -euo pipefail
cd "$1"
for tool in black flake8; do
  command -v "$tool" > /dev/null ||
    { echo "FAIL: $tool is not installed (bash scripts/install-deps.sh --test)"; exit 1; }
done
# The tracked files; a source tree without git: every .py file but the build folders'.
if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.py')
else
  mapfile -t files < <(find . \( -path './build*' -o -path './out' \) -prune -o \
                         -type f -name '*.py' -print | sort)
fi
status=0
# black names the files it would change; flake8 prints file:line:column and the finding.
black --check --line-length 100 "${files[@]}" || status=1
flake8 "${files[@]}" || status=1
if [ "$status" -ne 0 ]; then echo "FAIL: the Python style (black, flake8) above"; exit 1; fi
echo "python style: ${#files[@]} files ok"
