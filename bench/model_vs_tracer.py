#!/usr/bin/env python3
"""The model's host time against the reference tracer's for the same frame (issue 20's goal: the
model within 30x a production tracer's single-core time; our reference tracer stands in for one,
docs/BENCHMARKS.md compares it with Embree).

    python3 bench/model_vs_tracer.py [--build build] [--scene configs/scenes/robots.yaml]
        [--hw configs/hw/tni-paper.yaml] [--width 1920 --height 1080] [--runs 3] [--set K=V ...]
        [--rtsim BIN]   (the model's binary, default BUILD/rtsim: a profile-guided build's, say)

Tracer: build/bench/bench_tracer, one core, the frame's primary rays and one shadow ray per light
per hit (all of them: what a tracer without culling traces), median of --runs. Model: `rtsim run`
pinned to one core (culling as the scene file says, on by default), median of --runs of
report.json's host.seconds.simulate. The two alternate, so a slow phase of the machine hits both.
Prints both medians, model / tracer, and the simulated cycles per host second.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def tracer_seconds(args):
    cmd = [
        "taskset",
        "-c",
        "0",
        os.path.join(args.build, "bench", "bench_tracer"),
        args.scene,
        "--width",
        str(args.width),
        "--height",
        str(args.height),
        "--repeat",
        "1",
    ]
    out = subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True, text=True).stdout
    m = re.search(r"median seconds for the frame's rays: ([0-9.]+)", out)
    if not m:
        raise SystemExit(f"model_vs_tracer: no seconds in bench_tracer's output:\n{out}")
    rays = re.search(r"(\d+) primary rays, (\d+) shadow rays", out)
    return float(m.group(1)), int(rays.group(1)) + int(rays.group(2))


def model_run(args):
    with tempfile.TemporaryDirectory() as out:
        cmd = [
            "taskset",
            "-c",
            "0",
            args.rtsim or os.path.join(args.build, "rtsim"),
            "run",
            args.scene,
            "--hw",
            args.hw,
            "--width",
            str(args.width),
            "--height",
            str(args.height),
            "--out",
            out,
            "--no-plots",
            "--quiet",
        ]
        cmd += [x for s in args.set for x in ("--set", s)]
        subprocess.run(cmd, cwd=ROOT, check=True)
        with open(os.path.join(out, "report.json")) as f:
            r = json.load(f)
    return r["host"]["seconds"]["simulate"], r["cycles_total"]


def main():
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--build", default=os.path.join(ROOT, "build"))
    p.add_argument("--scene", default="configs/scenes/robots.yaml")
    p.add_argument("--hw", default="configs/hw/tni-paper.yaml")
    p.add_argument("--width", type=int, default=1920)
    p.add_argument("--height", type=int, default=1080)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--set", action="append", default=[], help="an override for the model's runs")
    p.add_argument("--rtsim", help="the model's binary (default: BUILD/rtsim)")
    args = p.parse_args()
    tracer, model = [], []
    cycles = rays = 0
    for k in range(args.runs):
        t, rays = tracer_seconds(args)
        m, cycles = model_run(args)
        tracer.append(t)
        model.append(m)
        print(
            f"run {k + 1}: tracer {t:.3f} s, model {m:.1f} s simulate ({cycles:,} cycles)",
            flush=True,
        )
    mt, mm = statistics.median(tracer), statistics.median(model)
    print(
        f"{os.path.basename(args.scene)} {args.width}x{args.height}: "
        f"tracer {mt:.3f} s for {rays:,} rays, model {mm:.1f} s; model / tracer = {mm / mt:.1f}x; "
        f"{cycles / mm / 1e3:.0f} k simulated cycles per host second (medians of {args.runs})"
    )


if __name__ == "__main__":
    main()
