#!/usr/bin/env python3
"""A sampled run's estimator on full runs' true unit cycles (docs/sampling.md), over many seeds:
the binary's plan and estimators (bench_sampling_draws: testbench/sampling/sample_plan.h and
testbench/run/sampled_frame.h's estimate_sampled, the regression on the functional pass and its
jackknife intervals) given every drawn unit's cycles exactly as the full run measured them. What it
prints bounds what a sampled run's estimator makes of the frame, whatever its warming adds. This
script only tabulates the draws.

  python3 bench/sampling_plan_study.py RUN... [--fractions 0.05] [--units 2048]
      [--strata neyman,issue] [--seeds 200] [--build build]

RUN: a full run's directory (config.json, batches.csv). Its functional pass and walk steps are
computed once (BUILD/bench/bench_sampling_features --pass RUN/sampling-pass.bin) and kept there.
Prints, per run, plan and phase (primary, shadow, frame), the largest, rms and 95th-percentile
error, the mean 95% half-interval and how many intervals held the truth.
"""
import argparse
import csv
import io
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def tool(build, name):
    return os.path.join(build, "bench", name)


def pass_file(run, build):
    """RUN/sampling-pass.bin: the run's functional pass and walk steps (1 ray in 4, as a run)."""
    path = os.path.join(run, "sampling-pass.bin")
    if not os.path.exists(path):
        subprocess.run(
            [tool(build, "bench_sampling_features"), "--config", os.path.join(run, "config.json")]
            + ["--out", os.path.join(run, "features.csv"), "--pass", path, "--steps-stride", "4"],
            check=True,
            cwd=ROOT,
            stdout=sys.stderr,
        )
    return path


def draws(run, build, fraction, unit, strata, seeds):
    """bench_sampling_draws' rows: seed, phase, truth, estimate, ci95, estimator, measured."""
    out = subprocess.run(
        [tool(build, "bench_sampling_draws"), "--config", os.path.join(run, "config.json")]
        + ["--pass", pass_file(run, build), "--fraction", str(fraction), "--unit", str(unit)]
        + ["--strata", strata, "--seeds", str(seeds)],
        check=True,
        capture_output=True,
        text=True,
        cwd=ROOT,
    ).stdout
    return list(csv.DictReader(io.StringIO(out)))


def percentile(v, q):
    """The q-th percentile, interpolated between the closest ranks."""
    v = sorted(v)
    x = q / 100 * (len(v) - 1)
    lo = math.floor(x)
    return v[lo] + (v[min(lo + 1, len(v) - 1)] - v[lo]) * (x - lo)


def rows(draws_):
    """Per phase: (measured units, estimator, errors, half-intervals, how many held), relative."""
    out = {}
    for r in draws_:
        if r["truth"] == "":
            raise SystemExit("bench_sampling_draws: not a full run (batches.csv has windows)")
        truth, est, ci = float(r["truth"]), float(r["estimate"]), float(r["ci95"])
        n, estimator, errs, halves, held = out.get(r["phase"], (r["measured"], "", [], [], 0))
        errs.append(abs(est - truth) / truth)
        halves.append(ci / truth)
        out[r["phase"]] = (n, r["estimator"], errs, halves, held + (abs(est - truth) <= ci))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--fractions", default="0.05")
    ap.add_argument("--units", default="2048", help="rays per unit (run.sample_unit)")
    ap.add_argument("--strata", default="neyman,issue", help="run.sample_strata: neyman, issue")
    ap.add_argument("--seeds", type=int, default=200)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    a = ap.parse_args()
    print(
        "| run | strata | fraction | unit | measured | phase | estimator | largest | rms "
        "| 95th percentile | mean 95% interval | held |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for run in a.runs:
        name = os.path.basename(os.path.normpath(run))
        for strata in a.strata.split(","):
            for f in a.fractions.split(","):
                for u in a.units.split(","):
                    got = rows(draws(run, a.build, f, u, strata, a.seeds))
                    for ph, (n, estimator, e, h, held) in got.items():
                        rms = math.sqrt(sum(x * x for x in e) / len(e))
                        print(
                            f"| {name} | {strata} | {f} | {u} | {n} | {ph} | {estimator} "
                            f"| {100 * max(e):.2f}% | {100 * rms:.2f}% "
                            f"| {100 * percentile(e, 95):.2f}% | {100 * sum(h) / len(h):.2f}% "
                            f"| {held} of {len(e)} |",
                            flush=True,
                        )


if __name__ == "__main__":
    main()
