#!/usr/bin/env python3
"""Sampling error alone (docs/sampling.md): the primary phase of full runs, estimated from
systematic samples of their batches (batches.csv) as a sampled run would if its warming were
perfect, for every start of the sample. What it prints bounds what warming can add to.

  python3 bench/sampling_ideal.py RUN_DIR... [--fraction 0.1] [--group G] [--phase shadow]

Per run: the units (G consecutive batches each), the primary phase, and over the k starts the
largest error of the estimate, the mean 95% half-interval (both in % of the phase) and how many
intervals held the true phase. The estimator is testbench/sampling/sample_estimate.cpp's, with z =
1.96
(Student's t would widen the intervals of samples under 31 units a little).
"""
import argparse
import csv
import math
import os


def estimate(values, population):
    n = len(values)
    mean = sum(values) / n
    s = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1))
    return population * mean, 1.96 * population * s / math.sqrt(n) * math.sqrt(1 - n / population)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--fraction", type=float, default=0.1)
    ap.add_argument("--group", type=int, default=1, help="batches per unit (contiguous)")
    ap.add_argument("--phase", choices=["primary", "shadow"], default="primary")
    a = ap.parse_args()
    k = max(1, round(1 / a.fraction))
    print(f"fraction {a.fraction}, {a.group} batches of 64 rays a unit")
    print("| run | units | primary cycles | largest error | mean 95% interval | held |")
    print("|---|---|---|---|---|---|")
    for run in a.runs:
        with open(os.path.join(run, "batches.csv"), newline="") as f:
            rows = csv.DictReader(f)  # files before the phase column hold the primary phase
            batches = [float(r["cycles"]) for r in rows if r.get("phase", "primary") == a.phase]
        g = a.group
        cycles = [sum(batches[i : i + g]) for i in range(0, len(batches), g)]
        truth = sum(cycles)
        errors, widths, held = [], [], 0
        for start in range(k):
            total, ci = estimate(cycles[start::k], len(cycles))
            errors.append(abs(total - truth) / truth)
            widths.append(ci / truth)
            held += abs(total - truth) <= ci
        print(
            f"| {os.path.basename(os.path.normpath(run))} | {len(cycles):,} | {truth:,.0f} | "
            f"{100 * max(errors):.2f}% | {100 * sum(widths) / k:.2f}% | {held} of {k} |"
        )


if __name__ == "__main__":
    main()
