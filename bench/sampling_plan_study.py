#!/usr/bin/env python3
"""A sampled run's estimator on a full run's true unit cycles (docs/sampling.md): the plan of
testbench/sample_plan.cpp (first and last unit always measured, one unit drawn per stratum of
round(1/F) units) and the estimators of testbench/sample_regression.cpp (GREG on the functional
pass's features, the frame's interval from both phases' residuals by successive differences),
over many seeds, as if every drawn unit were measured exactly: the bound that the estimator puts
on a sampled run, whatever its warming.

  bench_sampling_features --config RUN/config.json --out features.csv
  /usr/bin/python3 bench/sampling_plan_study.py RUN features.csv [--fraction 0.05] [--seeds 200]

RUN: a full run's directory (batches.csv with the phase column). Prints, per estimator, the
largest, rms and 95th-percentile error of the frame's cycles, the mean 95% half-interval and how
many intervals held the truth.
"""
import argparse
import csv

import numpy as np

T975 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179]
T975 += [2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064]
T975 += [2.060, 2.056, 2.052, 2.048, 2.045, 2.042]
UNIT = 32  # batches of 64 rays: run.sample_unit 2,048
IN_FLIGHT = 12  # batches: the traversal units' rays (24 x (16 + 16)) over 64


def t95(dof):
    return T975[dof - 1] if 0 < dof <= 30 else 1.96


def units(x):
    return np.add.reduceat(np.asarray(x, dtype=float), np.arange(0, len(x), UNIT))


def ahead(x):
    """Each batch's figure over the batches in flight ahead of it."""
    out = np.zeros_like(x)
    for k in range(IN_FLIGHT, 2 * IN_FLIGHT):
        out[k:] += x[:-k]
    return out


def load(run, features):
    y = {"primary": [], "shadow": []}
    with open(f"{run}/batches.csv", newline="") as f:
        for r in csv.DictReader(f):
            y[r["phase"]].append(float(r["cycles"]))
    with open(features, newline="") as f:
        rows = list(csv.DictReader(f))
    feat = {}
    for ph in ("primary", "shadow"):
        rr = [r for r in rows if r.get("phase", "primary") == ph]
        feat[ph] = {k: np.array([float(r[k]) for r in rr]) for k in rr[0] if k != "phase"}
    p = feat["primary"]
    l1 = sum(p[f"{t}_l1_misses"] for t in ("trv", "list", "ist", "shading"))
    xp = np.column_stack(
        [units(p["replay_cycles"]), units(p["ist_reads"]), units(ahead(p["ist_reads"]))]
        + [units(l1), units(ahead(l1))]
    )
    xs = units(feat["shadow"]["replay_cycles"])[:, None]
    return units(y["primary"]), units(y["shadow"]), xp, xs


def plan(n_units, fraction, seed):
    k = max(1, round(1 / fraction))
    rng = np.random.default_rng(seed)
    out, first = [(0, 1, True)], 1
    while first + 1 < n_units:
        size = min(k, n_units - 1 - first)
        out.append((first + int(rng.integers(size)), size, False))
        first += k
    return out + [(n_units - 1, 1, True)]


def greg(y, x, sample, cols):
    """The total and the drawn units' weighted residuals (each over 1 - its leverage)."""
    cert = [i for i, _, c in sample if c]
    idx = np.array([i for i, _, c in sample if not c])
    w = np.array([float(s) for _, s, c in sample if not c])
    if cols is None:
        return y[cert].sum() + np.sum(w * y[idx]), w * y[idx], 1
    a = np.column_stack([np.ones(len(y)), x[:, cols]])
    a = a / np.abs(a).mean(axis=0)
    ad = a[idx]
    m = ad.T @ (w[:, None] * ad)
    beta = np.linalg.solve(m, ad.T @ (w * y[idx]))
    rest = np.ones(len(y), bool)
    rest[cert] = False
    e = y[idx] - ad @ beta
    total = y[cert].sum() + (a[rest] @ beta).sum() + np.sum(w * e)
    lev = w * np.einsum("ij,jk,ik->i", ad, np.linalg.inv(m), ad)
    return total, w * e / np.maximum(1 - lev, 0.05), a.shape[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("features")
    ap.add_argument("--fraction", type=float, default=0.05)
    ap.add_argument("--seeds", type=int, default=200)
    a = ap.parse_args()
    yp, ys, xp, xs = load(a.run, a.features)
    truth = (yp + ys).sum()
    estimators = [
        ("expansion", None, None),
        ("GREG: replay", [0], [0]),
        ("GREG: replay, IST reads, L1 misses (the run's)", [0, 1, 2, 3, 4], [0]),
    ]
    print(f"{a.run}: {len(yp)} units, fraction {a.fraction}, {a.seeds} seeds")
    print("| estimator | largest | rms | 95th percentile | mean 95% interval | held |")
    print("|---|---|---|---|---|---|")
    for name, cp, cs in estimators:
        errs, halves, held = [], [], 0
        for seed in range(1, a.seeds + 1):
            sample = plan(len(yp), a.fraction, seed)
            tp, rp, p = greg(yp, xp, sample, cp)
            ts, rs, _ = greg(ys, xs, sample, cs)
            n = len(rp)
            fpc = 1 - n / sum(s for _, s, c in sample if not c)
            r = rp + rs
            half = t95(n - p) * np.sqrt(n * fpc * np.sum(np.diff(r) ** 2) / (2 * (n - 1)))
            errs.append(abs(tp + ts - truth) / truth)
            halves.append(half / truth)
            held += abs(tp + ts - truth) <= half
        e = np.array(errs)
        print(
            f"| {name} | {100 * e.max():.2f}% | {100 * np.sqrt(np.mean(e**2)):.2f}% | "
            f"{100 * np.percentile(e, 95):.2f}% | {100 * np.mean(halves):.2f}% | "
            f"{held} of {a.seeds} |"
        )


if __name__ == "__main__":
    main()
