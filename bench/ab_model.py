#!/usr/bin/env python3
"""A/B host time of the SystemC model: two rtsim binaries (each with its own hardware file), run
alternately on one scene, one core each, several times; prints each run and the medians of the
simulation's host seconds (report.json host.seconds.simulate) and their ratio.

    python3 bench/ab_model.py --a BIN_A:HW_A --b BIN_B:HW_B --scene configs/scenes/robots.yaml \
        [--width 1920 --height 1080] [--runs 3] [--set KEY=VALUE ...]

Run it on a quiet machine: the two are compared in one session, in alternation, so that a slow
phase of the machine hits both. taskset pins every run to one core (the simulator is
single-threaded; the kd-tree and LVB steps before it may use more, which this does not time).
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile


def run(binary, hw, args, extra):
    with tempfile.TemporaryDirectory() as out:
        cmd = [
            "taskset",
            "-c",
            "0",
            binary,
            "run",
            args.scene,
            "--hw",
            hw,
            "--out",
            out,
            "--no-plots",
            "--quiet",
            "--width",
            str(args.width),
            "--height",
            str(args.height),
        ] + extra
        subprocess.run(cmd, check=True)
        with open(os.path.join(out, "report.json")) as f:
            r = json.load(f)
    return r["host"]["seconds"]["simulate"], r["cycles_total"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--a", required=True, help="BIN:HW, the baseline")
    p.add_argument("--b", required=True, help="BIN:HW, the candidate")
    p.add_argument("--scene", required=True)
    p.add_argument("--width", type=int, default=1920)
    p.add_argument("--height", type=int, default=1080)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--set", action="append", default=[], help="an override for both")
    args = p.parse_args()
    extra = [x for s in args.set for x in ("--set", s)]
    sides = {"a": args.a.split(":", 1), "b": args.b.split(":", 1)}
    seconds = {"a": [], "b": []}
    for k in range(args.runs):
        for side in ("a", "b"):
            binary, hw = sides[side]
            s, cycles = run(binary, hw, args, extra)
            seconds[side].append(s)
            print(
                f"run {k + 1} {side}: {s:.3f} s simulate, {cycles:,} cycles ({binary}, {hw})",
                flush=True,
            )
    ma, mb = statistics.median(seconds["a"]), statistics.median(seconds["b"])
    print(f"median a {ma:.3f} s, b {mb:.3f} s, b / a = {mb / ma:.3f}")


if __name__ == "__main__":
    main()
