#!/usr/bin/env python3
"""The model's host time per simulated ray, kd-tree machine against BVH machines (issue 37's
goal: a BVH within 1.5x of the kd-tree's time per ray on robots).

    python3 bench/model_per_ray.py [--build build] [--scene configs/scenes/robots.yaml]
        [--width 480 --height 270] [--runs 3] [--accel bvh2,bvh4,bvh8,cwbvh8]

Each run is `rtsim run` pinned to one core, culling on (the exact mode): the kd-tree on
configs/hw/tni-paper.yaml, each BVH format on configs/hw/bvh-tni.yaml. A ray is one the traversal
units started (primary, shadow and reflection rays: the statistic report.json's `units` names as
`rays`); the time is report.json's host.seconds.simulate. The setups alternate within a round, so
a slow phase of the machine hits all of them; medians over --runs rounds, and each BVH's ratio to
the kd-tree.
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(args, accel):
    hw = "configs/hw/tni-paper.yaml" if accel == "kdtree" else "configs/hw/bvh-tni.yaml"
    with tempfile.TemporaryDirectory() as out:
        cmd = ["taskset", "-c", "0", os.path.join(args.build, "rtsim"), "run", args.scene]
        cmd += ["--hw", hw, "--accel", accel, "--width", str(args.width)]
        cmd += ["--height", str(args.height), "--out", out, "--no-plots", "--quiet"]
        subprocess.run(cmd, cwd=ROOT, check=True)
        with open(os.path.join(out, "report.json")) as f:
            r = json.load(f)
    # The rays the report's per-ray figures divide: the traversal type's `rays` statistic.
    node = r["stats"]
    for part in next(u["rays"] for u in r["units"] if "rays" in u).split("."):
        node = node[part]
    rays = node
    return r["host"]["seconds"]["simulate"], rays, r["cycles_total"]


def main():
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--build", default=os.path.join(ROOT, "build"))
    p.add_argument("--scene", default="configs/scenes/robots.yaml")
    p.add_argument("--width", type=int, default=480)
    p.add_argument("--height", type=int, default=270)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--accel", default="bvh2,bvh4,bvh8,cwbvh8")
    args = p.parse_args()
    setups = ["kdtree"] + [a for a in args.accel.split(",") if a]
    per_ray = {a: [] for a in setups}
    facts = {}
    for k in range(args.runs):
        for a in setups:
            seconds, rays, cycles = run(args, a)
            per_ray[a].append(seconds / rays)
            facts[a] = (rays, cycles)
            print(
                f"round {k + 1}: {a}: {seconds:.2f} s, {rays:,} rays, {cycles:,} cycles", flush=True
            )
    base = statistics.median(per_ray["kdtree"])
    print(f"\n{os.path.basename(args.scene)} {args.width}x{args.height}, medians of {args.runs}:")
    print("| structure | rays | cycles | host us per ray | vs kd-tree |\n|---|---|---|---|---|")
    for a in setups:
        m = statistics.median(per_ray[a])
        rays, cycles = facts[a]
        print(f"| {a} | {int(rays):,} | {cycles:,} | {1e6 * m:.2f} | {m / base:.2f}x |")


if __name__ == "__main__":
    main()
