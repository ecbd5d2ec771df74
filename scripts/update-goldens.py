#!/usr/bin/env python3
"""Rewrites the timing goldens in tests/golden/ from the current model.

    python3 scripts/update-goldens.py [--check] [build/rtsim]

Each golden file names an rtsim command line ("args") and the figures it must produce ("expect").
This script runs each command and writes the figures back, listing every value that changed.
A golden marked "frozen" (the ideal memory system: the model as it was before contention was
modelled) is never rewritten: if it differs, the script fails, because an ideal setting no longer
reproduces the old model. With --check nothing is written; the exit code says whether all match.
A changed golden needs a line in docs/timing-changes.md and a reason in the commit message.
"""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GOLDEN = os.path.join(ROOT, "tests", "golden")

# What a golden pins: the frame, every unit type's time split and every cache level, as the
# report lists them (its `units` and `caches`), and the DRAM.
FRAME = ["cycles_total", "cycles_primary", "cycles_shadow"]
UNIT_FIGURES = ("busy_cycles", "stalled_cycles", "idle_cycles")
CACHE_FIGURES = ("accesses", "hits", "misses")
DRAM = ["stats.dram.reads", "stats.dram.row_hits", "stats.dram.activates"]


def keys(report):
    units = [f"stats.{u['stats']}.{k}" for u in report["units"] for k in UNIT_FIGURES]
    caches = [f"stats.{c['key']}.{k}" for c in report["caches"] for k in CACHE_FIGURES]
    return FRAME + units + caches + DRAM


def lookup(report, path):
    node = report
    for part in path.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    return node


def measure(binary, args):
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([binary, *args, "--out", out, "--no-plots", "--quiet"], cwd=ROOT, check=True)
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
    figures = {}
    for key in keys(report):
        value = lookup(report, key)
        if value is None:
            sys.exit(f"{key}: not in the report of rtsim {' '.join(args)}")
        figures[key] = int(value) if float(value).is_integer() else value
    return figures


def main():
    argv = sys.argv[1:]
    check = "--check" in argv
    argv = [a for a in argv if a != "--check"]
    binary = os.path.abspath(argv[0]) if argv else os.path.join(ROOT, "build", "rtsim")
    failed = False
    for name in sorted(os.listdir(GOLDEN)):
        if not name.endswith(".json"):
            continue
        path = os.path.join(GOLDEN, name)
        with open(path) as f:
            golden = json.load(f)
        figures = measure(binary, golden["args"])
        old = golden.get("expect", {})
        changes = [(k, old.get(k), v) for k, v in figures.items() if old.get(k) != v]
        changes += [(k, v, None) for k, v in old.items() if k not in figures]
        for key, before, after in changes:
            print(f"{name}: {key}: {before} -> {after}")
        if not changes:
            print(f"{name}: unchanged")
            continue
        if golden.get("frozen") and old:
            print(f"{name}: frozen (the ideal memory system must reproduce these): not rewritten")
            failed = True
            continue
        if check:
            failed = True
            continue
        # The figures in the golden's order (new ones last), so that a rewrite moves no line.
        order = [k for k in old if k in figures] + [k for k in figures if k not in old]
        golden["expect"] = {k: figures[k] for k in order}
        tmp = path + ".tmp"
        with open(tmp, "w") as f:
            json.dump(golden, f, indent=2)
            f.write("\n")
        os.replace(tmp, path)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
