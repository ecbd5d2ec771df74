#!/usr/bin/env python3
"""Host time of a run priced against the same run unpriced (issue 53's goal: within 3%, robots at
480x270 on tni-paper.yaml).

    python3 bench/energy_overhead.py [--build build] [--scene configs/scenes/robots.yaml]
        [--width 480 --height 270] [--runs 5]

Each run is `rtsim run` pinned to one core; `hw.energy` is 65nm (the default) or none. The two
settings alternate within a round, so a slow phase of the machine hits both; the table gives the
medians over --runs rounds of report.json's host.seconds.simulate (the frame, pricing included:
Accelerator::result prices it) and host.seconds.total, and their ratios. Both settings simulate
the same frame: the script checks that their cycles agree.
"""
import argparse
import os
import statistics

from model_per_ray import ROOT, pinned_report


def run(args, energy):
    options = ["--hw", "configs/hw/tni-paper.yaml", "--width", str(args.width)]
    options += ["--height", str(args.height), "--set", f"hw.energy={energy}"]
    r = pinned_report(args.build, args.scene, options)
    s = r["host"]["seconds"]
    return s["simulate"], s["total"], r["cycles_total"]


def main():
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--build", default=os.path.join(ROOT, "build"))
    p.add_argument("--scene", default="configs/scenes/robots.yaml")
    p.add_argument("--width", type=int, default=480)
    p.add_argument("--height", type=int, default=270)
    p.add_argument("--runs", type=int, default=5)
    args = p.parse_args()
    settings = ["none", "65nm"]
    times = {e: ([], []) for e in settings}
    cycles = set()
    for i in range(args.runs):
        for e in settings:
            sim, total, c = run(args, e)
            times[e][0].append(sim)
            times[e][1].append(total)
            cycles.add(c)
            print(
                f"round {i + 1}: energy {e}: simulate {sim:.2f} s, total {total:.2f} s", flush=True
            )
    if len(cycles) != 1:
        raise SystemExit(f"the settings simulated different frames: cycles {sorted(cycles)}")
    base = [statistics.median(t) for t in times["none"]]
    print(f"\n{os.path.basename(args.scene)} {args.width}x{args.height}, medians of {args.runs}:")
    print("| energy | simulate (s) | total (s) | simulate vs none | total vs none |")
    print("|---|---|---|---|---|")
    for e in settings:
        sim, total = (statistics.median(t) for t in times[e])
        print(f"| {e} | {sim:.2f} | {total:.2f} | {sim / base[0]:.3f}x | {total / base[1]:.3f}x |")


if __name__ == "__main__":
    main()
