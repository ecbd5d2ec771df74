#!/usr/bin/env python3
"""Sampled frames (issue 38): how well the functional pass's per-batch features predict a full
run's per-batch cycles: R^2 of units' cycles on each feature and its lags. What a sampled estimate
built on them is worth is bench/sampling_plan_study.py's (the binary's estimators).

    /usr/bin/python3 bench/sampling_regression.py RUN_DIR:FEATURES_CSV [...] [--units 1,8,32,64]
        [--phases primary,shadow,frame]

RUN_DIR holds a full run's batches.csv (phase,batch,first,cycles: the cycles per 64-ray batch of
the primary phase in issue order and, in two phases, per 64 record slots of the shadow phase; a
file without the phase column is the primary phase's alone), report.json and config.json;
FEATURES_CSV is bench_sampling_features' output for the same frame
(model/functional/batch_features.h's write_features_csv: reads, L1 misses and DRAM lines by stage,
hits, shadow rays emitted and culled, and the replay's own cycles, per phase). "frame" is a unit's
primary and shadow cycles together (the same batches of slots in both phases). For each phase and
unit size (batches per unit) it prints R^2 of the units' cycles on each feature: the unit's own
(lag 0), the best single lag, and a least-squares fit on lags 0..L (in-sample); then on every
feature with lags 0..L together. L covers the rays in flight twice: a batch's cycles are the
machine's throughput while it issues, which the rays issued a few hundred rays earlier set (the
traversal units hold count x (capacity + fifo_depth) rays, config.json).
"""
import argparse
import csv
import json
import math
import os

import numpy as np

# The features' stages (their columns' prefixes: the report's stage names).
STAGES = ("traversal", "list", "ist", "shading")
R2_FEATURES = (
    "traversal_reads",
    "leaves",
    "ist_reads",
    "l1_misses",
    "ist_l1_misses",
    "dram_lines",
    "hits",
    "rays",
    "culled",
    "l2_floor",
    "replay_cycles",
)


def read_phases(path):
    """The CSV's columns by phase (rows without a phase column are the primary phase's)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    by_phase = {}
    for r in rows:
        by_phase.setdefault(r.get("phase", "primary"), []).append(r)
    return {
        ph: {k: np.array([float(r[k]) for r in rs]) for k in rs[0] if k != "phase"}
        for ph, rs in by_phase.items()
    }


def derive(feats, hw, traversal):
    """`traversal`: the hardware file's section of the traversal stage's unit type."""
    feats["leaves"] = feats["list_reads"] / 2
    for what in ("l1_misses", "dram_lines", "l1_lines"):
        feats[what] = sum(feats[t + "_" + what] for t in STAGES)
    # The cycles the L2s' banks take to send the L1 misses' lines back (a line's flits a bank),
    # the busiest L2's: a floor under a batch's cycles that the replay does not model. The
    # shading unit reads through IST's L2.
    floors = []
    for section, misses in (
        (traversal, feats["traversal_l1_misses"]),
        ("list", feats["list_l1_misses"]),
        ("ist", feats["ist_l1_misses"] + feats["shading_l1_misses"]),
    ):
        link = hw[section]["link"]
        flits = math.ceil((64 + link["header_bytes"]) / max(1, link["bytes_per_cycle"]))
        floors.append(misses * flits / hw[section]["l2"]["banks"])
    feats["l2_floor"] = np.maximum.reduce(floors)
    return feats


def load(run_dir, features_csv):
    """Per phase (and "frame"): the run's batch cycles, the rays in flight in batches, and the
    features by name."""
    runs = read_phases(os.path.join(run_dir, "batches.csv"))
    with open(os.path.join(run_dir, "report.json")) as f:
        report = json.load(f)
    with open(os.path.join(run_dir, "config.json")) as f:
        hw = json.load(f)["hw"]
    # The traversal stage's unit type (report.json's units), its section of the hardware file.
    traversal = next(u["key"] for u in report["units"] if u.get("stage") == "traversal")
    trv = hw[traversal]
    in_flight = trv["count"] * (trv["capacity"] + trv["fifo_depth"])
    feats = read_phases(features_csv)
    out = {}
    for phase, cycles in ((ph, runs[ph]["cycles"]) for ph in runs):
        if int(cycles.sum()) != report["cycles_" + phase]:
            raise SystemExit(f"{run_dir}: batches.csv does not add up to cycles_{phase}")
        if phase not in feats or len(feats[phase]["batch"]) != len(cycles):
            raise SystemExit(f"{features_csv}: not the run's {len(cycles)} {phase} batches")
        f = derive(feats[phase], hw, traversal)
        rays_per_batch = max(1.0, float(f["rays"].mean()))
        out[phase] = (cycles, max(1, round(in_flight / rays_per_batch)), f)
    if "shadow" in out:
        (cp, dp, fp), (cs, ds, fs) = out["primary"], out["shadow"]
        both = {k: fp[k] + fs[k] for k in fp if k in fs}
        both["phases"] = (fp, dp, fs, ds)
        out["frame"] = (cp + cs, max(dp, ds), both)
    return out


def shifted(x, lag):
    """x delayed by `lag` entries (zeros before the start)."""
    if lag == 0:
        return x.copy()
    out = np.zeros_like(x)
    out[lag:] = x[:-lag]
    return out


def to_units(x, g):
    """Sums of g consecutive batches (the last unit maybe shorter)."""
    n = len(x)
    pad = (-n) % g
    return np.concatenate([x, np.zeros(pad)]).reshape(-1, g).sum(axis=1)


def lag_matrix(x, lags):
    return np.column_stack([shifted(x, lag) for lag in lags])


def r2(y, x):
    a = np.column_stack([np.ones(len(y)), x])
    beta, *_ = np.linalg.lstsq(a, y, rcond=None)
    e = y - a @ beta
    return 1.0 - e.var() / y.var() if y.var() > 0 else float("nan")


def unit_lags(g, depth):
    """Lags in units covering the rays in flight twice over: 0..ceil(2 x depth / g)."""
    return range(0, max(1, math.ceil(2 * depth / g)) + 1)


def r2_rows(cycles, feats, g, depth):
    """Per feature: R^2 on its own unit, on its best single lag (and which), on lags 0..L."""
    y = to_units(cycles, g)
    lags = unit_lags(g, depth)
    rows, every = [], []
    for name in R2_FEATURES:
        x = to_units(feats[name], g)
        if x.var() == 0:
            rows.append((name, float("nan"), float("nan"), 0, float("nan")))
            continue
        singles = [r2(y, shifted(x, lag)) for lag in lags]
        best = int(np.nanargmax(singles))
        m = lag_matrix(x, lags)
        every.append(m)
        rows.append((name, singles[0], singles[best], best, r2(y, m)))
    rows.append(("all above", float("nan"), float("nan"), 0, r2(y, np.column_stack(every))))
    return rows, lags


def print_r2(name, phase, cycles, feats, depth, units):
    print(f"\n## {name}, {phase}: R^2 of unit cycles (in flight: {depth} batches)\n")
    print("| unit | feature | own unit | best lag (units) | lags 0..L |")
    print("|---|---|---|---|---|")
    for g in units:
        rows, lags = r2_rows(cycles, feats, g, depth)
        for feat, own, best, lag, many in rows:
            best_s = "" if math.isnan(best) else f"{best:.3f} ({lag})"
            own_s = "" if math.isnan(own) else f"{own:.3f}"
            print(f"| {g} x 64 | {feat} | {own_s} | {best_s} | {many:.3f} (L={lags[-1]}) |")


def main():
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("pairs", nargs="+", help="RUN_DIR:FEATURES_CSV")
    p.add_argument("--units", default="1,8,32,64")
    p.add_argument("--phases", default="primary,shadow,frame")
    args = p.parse_args()
    args.units = [int(u) for u in args.units.split(",")]
    for pair in args.pairs:
        run_dir, features_csv = pair.split(":")
        phases = load(run_dir, features_csv)
        name = os.path.basename(os.path.normpath(run_dir))
        for phase in (ph for ph in args.phases.split(",") if ph in phases):
            cycles, depth, feats = phases[phase]
            cv = cycles.std() / cycles.mean()
            print(
                f"\n# {name}, {phase}: {len(cycles)} batches, {int(cycles.sum())} cycles, "
                f"CV {cv:.2f}"
            )
            print_r2(name, phase, cycles, feats, depth, args.units)


if __name__ == "__main__":
    main()
