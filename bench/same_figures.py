#!/usr/bin/env python3
"""Whether two rtsim binaries simulate the same frames: every figure of report.json but the host's
(timing, memory) equal, and the same image bytes, on a set of small runs that cover the model's
paths (both schedules, culling on and off, the paper's method, reflections, area lights, the
ideal and the small memory system, the TLM checker). A speed change must
pass this before its A/B (bench/ab_model.py) means anything.

    python3 bench/same_figures.py --a BIN_A --b BIN_B [--jobs 2] [--only NAME,...] [--ignore KEYS]
        [--added-ok]

Exit 0 when every run matches, 1 when one differs (the first differing keys are printed).
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def args(scene, hw, width, height, *extra):
    """Arguments after `rtsim run`: a scene and hardware file of configs/ at a resolution."""
    return [f"configs/scenes/{scene}.yaml", "--hw", f"configs/hw/{hw}.yaml"] + [
        "--width",
        str(width),
        "--height",
        str(height),
        *extra,
    ]


# name: arguments after `rtsim run`
RUNS = {
    "city-tni": args("city", "tni-paper", 160, 90),
    "city-small": args("city", "small", 160, 90),
    "city-ideal": args("city", "ideal", 160, 90),
    "robots-on": args("robots", "tni-paper", 160, 90),
    "robots-off": args("robots", "tni-paper", 160, 90, "--lvb", "off"),
    "robots-one-phase": args("robots", "tni-paper", 160, 90, "--set", "hw.schedule=one-phase"),
    "kitchen-paper": args(
        "kitchen", "tni-paper", 120, 68, "--set", "run.lvb_self_occlusion=ignore"
    ),
    "kitchen-reflect": args("kitchen", "small", 64, 36, "--reflections", "1"),
    "bunny-area": args(
        "bunny-area", "tni-paper", 96, 54, "--set", "scene.lights.area_from_points.samples=4"
    ),
    "city-checked": args("city", "tni-paper", 96, 54, "--set", "run.tlm_checks=true"),
}


def without_host(node):
    if isinstance(node, dict):
        return {k: without_host(v) for k, v in node.items() if k not in ("host", "host_seconds")}
    if isinstance(node, list):
        return [without_host(v) for v in node]
    return node


def run(binary, args, out):
    cmd = [binary, "run", *args, "--out", out, "--quiet", "--no-plots"]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(
            f"same_figures: {' '.join(cmd)} failed ({done.returncode}):\n{done.stderr}"
        )
    with open(os.path.join(out, "report.json")) as f:
        report = without_host(json.load(f))
    image = (
        open(os.path.join(out, "render.png"), "rb").read()
        if os.path.exists(os.path.join(out, "render.png"))
        else b""
    )
    return report, image


def differences(a, b, path="", added_ok=False):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if added_ok and k not in a:
                continue  # a field B has and A's format lacks: not a figure that moved
            yield from differences(a.get(k), b.get(k), f"{path}.{k}" if path else k, added_ok)
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            yield from differences(x, y, f"{path}[{i}]", added_ok)
    elif a != b:
        yield f"{path}: {a!r} != {b!r}"


def compare(name, args, a, b, ignore=(), added_ok=False):
    with tempfile.TemporaryDirectory() as tmp:
        ra, ia = run(a, args, os.path.join(tmp, "a"))
        rb, ib = run(b, args, os.path.join(tmp, "b"))
    for key in ignore:
        ra.pop(key, None)
        rb.pop(key, None)
    diff = list(differences(ra, rb, added_ok=added_ok))
    if ia != ib:
        diff.append("render.png differs")
    return name, diff, ra.get("cycles_total")


def main():
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--a", required=True, help="the baseline binary")
    p.add_argument("--b", required=True, help="the candidate binary")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--only", default="", help="comma-separated run names (default: all)")
    p.add_argument(
        "--ignore",
        default="",
        help="comma-separated top-level report.json keys to leave out, for binaries on either side "
        "of a report format change (schema: rtsim-report/2 against /3)",
    )
    p.add_argument(
        "--added-ok",
        action="store_true",
        help="fields only B's report has (a new configuration key, a new list) are not differences",
    )
    args = p.parse_args()
    names = [n for n in args.only.split(",") if n] or list(RUNS)
    unknown = [n for n in names if n not in RUNS]
    if unknown:
        print(
            f"same_figures: unknown run {', '.join(unknown)}; known: {', '.join(RUNS)}",
            file=sys.stderr,
        )
        sys.exit(2)
    a, b = os.path.abspath(args.a), os.path.abspath(args.b)
    failed = 0
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        ignore = [k for k in args.ignore.split(",") if k]
        for name, diff, cycles in pool.map(
            lambda n: compare(n, RUNS[n], a, b, ignore, args.added_ok), names
        ):
            print(
                f"{name:18} {'same' if not diff else 'DIFFERENT'}  ({cycles:,} cycles)", flush=True
            )
            for d in diff[:10]:
                print("   ", d)
            failed += bool(diff)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
