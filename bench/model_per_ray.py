#!/usr/bin/env python3
"""The model's host time per simulated ray, kd-tree machine against BVH machines (issue 37's
goal: a BVH within 1.5x of the kd-tree's time per ray on robots), and path-traced frames against
Whitted frames (issue 52's goal: within 1.5x, 480x270 on tni-paper.yaml).

    python3 bench/model_per_ray.py [--build build] [--scene configs/scenes/robots.yaml]
        [--width 480 --height 270] [--runs 3] [--accel bvh2,bvh4,bvh8,cwbvh8]
        [--integrators whitted,path:0,path] [--paired]

Each run is `rtsim run` pinned to one core, culling on (the exact mode): the kd-tree on
configs/hw/tni-paper.yaml, each BVH format on configs/hw/bvh-tni.yaml. A ray is one the traversal
units started (primary, shadow, reflection and bounce rays: the statistic report.json's `units`
names as `rays`); the time is report.json's host.seconds.simulate. A path-traced frame traces 1
path a pixel, 3 bounces (run.integrator: path), or D bounces (path:D): path:0 traces the Whitted
frame's rays through the path machinery, the control for its overhead. The table gives each
setup's DRAM reads per ray too: the simulated memory traffic a ray makes the host simulate. The
setups (structure x integrator) alternate within a round, so a slow phase of the machine hits all
of them; medians over --runs rounds, and each setup's ratio to the first (the kd-tree's Whitted
frame).

With --paired, each round runs every other setup once on one core while the first runs again and
again on the other (the cores swap each round); a setup's ratio is its time per ray over the mean
of the first's runs that overlapped it, and the table gives the median ratio. On a machine whose
speed drifts within minutes, the two then see the same drift (and share the last-level cache).
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile
import threading

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def pinned_report(build, scene, options, core=0):
    """report.json of `rtsim run SCENE OPTIONS`, pinned to one core (energy_overhead.py uses it)."""
    with tempfile.TemporaryDirectory() as out:
        cmd = ["taskset", "-c", str(core), os.path.join(build, "rtsim"), "run", scene]
        cmd += options + ["--out", out, "--no-plots", "--quiet"]
        subprocess.run(cmd, cwd=ROOT, check=True)
        with open(os.path.join(out, "report.json")) as f:
            return json.load(f)


def run(args, accel, integrator, core=0):
    name, _, depth = integrator.partition(":")
    hw = "configs/hw/tni-paper.yaml" if accel == "kdtree" else "configs/hw/bvh-tni.yaml"
    options = ["--hw", hw, "--accel", accel, "--width", str(args.width)]
    options += ["--height", str(args.height)]
    options += ["--integrator", name] + (["--max-depth", depth] if depth else [])
    r = pinned_report(args.build, args.scene, options, core)
    # The rays the report's per-ray figures divide: the traversal type's `rays` statistic.
    node = r["stats"]
    for part in next(u["rays"] for u in r["units"] if "rays" in u).split("."):
        node = node[part]
    rays = node
    dram = r["stats"]["dram"]["reads"]
    return r["host"]["seconds"]["simulate"], rays, r["cycles_total"], dram


def paired(args, setups):
    """--paired: each setup after the first against the first's runs beside it."""
    ratios = {s: [] for s in setups[1:]}
    for k in range(args.runs):
        here, there = k % 2, 1 - k % 2
        for s in setups[1:]:
            result = {}
            worker = threading.Thread(target=lambda: result.update(r=run(args, *s, here)))
            worker.start()
            firsts = []
            while worker.is_alive():
                seconds, rays, _, _ = run(args, *setups[0], there)
                firsts.append(seconds / rays)
            worker.join()
            seconds, rays, _, _ = result["r"]
            ratios[s].append(seconds / rays / statistics.mean(firsts))
            print(f"round {k + 1}: {s[0]} {s[1]}: {ratios[s][-1]:.3f}x", flush=True)
    print(f"\n{os.path.basename(args.scene)} {args.width}x{args.height}, paired, medians:")
    print("| structure | frame | vs the first |\n|---|---|---|")
    for s in setups[1:]:
        print(f"| {s[0]} | {s[1]} | {statistics.median(ratios[s]):.2f}x |")


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
    p.add_argument("--integrators", default="whitted")
    p.add_argument("--paired", action="store_true", help="the first beside each other at once")
    args = p.parse_args()
    structures = ["kdtree"] + [a for a in args.accel.split(",") if a]
    integrators = [i for i in args.integrators.split(",") if i]
    setups = [(a, i) for a in structures for i in integrators]
    if args.paired:
        return paired(args, setups)
    per_ray = {s: [] for s in setups}
    facts = {}
    for k in range(args.runs):
        for s in setups:
            seconds, rays, cycles, dram = run(args, *s)
            per_ray[s].append(seconds / rays)
            facts[s] = (rays, cycles, dram)
            print(
                f"round {k + 1}: {s[0]} {s[1]}: {seconds:.2f} s, {rays:,} rays, {cycles:,} cycles",
                flush=True,
            )
    base = statistics.median(per_ray[setups[0]])
    print(f"\n{os.path.basename(args.scene)} {args.width}x{args.height}, medians of {args.runs}:")
    print(
        "| structure | frame | rays | cycles | DRAM reads per ray | host us per ray "
        "| vs the first |\n|---|---|---|---|---|---|---|"
    )
    for s in setups:
        m = statistics.median(per_ray[s])
        rays, cycles, dram = facts[s]
        print(
            f"| {s[0]} | {s[1]} | {int(rays):,} | {cycles:,} | {dram / rays:.2f} | {1e6 * m:.2f} "
            f"| {m / base:.2f}x |"
        )


if __name__ == "__main__":
    main()
