#!/usr/bin/env python3
"""Sampled frames (issue 38): how well the functional pass's per-batch features predict a full
run's per-batch cycles, and what a sampled estimate of a phase, or of the frame, built on them is
worth.

    /usr/bin/python3 bench/sampling_regression.py RUN_DIR:FEATURES_CSV [...] [--draws 40]
        [--seed 1] [--units 1,8,32,64] [--fractions 0.02,0.05,0.1] [--no-r2]
        [--phases primary,shadow,frame] [--certain 0,1] [--sorted]

RUN_DIR holds a full run's batches.csv (phase,batch,first,cycles: the cycles per 64-ray batch of
the primary phase in issue order and, in two phases, per 64 record slots of the shadow phase; a
file without the phase column is the primary phase's alone), report.json and config.json;
FEATURES_CSV is bench_sampling_features' output for the same frame
(testbench/run/sampling_features.h:
reads, L1 misses and DRAM lines by unit type, hits, shadow rays emitted and culled, and the
replay's own cycles, per phase). "frame" is a unit's primary and shadow cycles together (the same
batches of slots in both phases). For each phase and unit size (batches per unit) it prints:
- R^2 of the units' cycles on each feature: the unit's own (lag 0), the best single lag, and a
  least-squares fit on lags 0..L (in-sample); then on every feature with lags 0..L together.
  L covers the rays in flight twice: a batch's cycles are the machine's throughput while it
  issues, which the rays issued a few hundred rays earlier set (the traversal units hold
  count x (capacity + fifo_depth) rays, config.json);
- the estimators of the primary phase's total from a stratified sample (one unit drawn at random
  in each stratum of k = round(1/f) consecutive units), over --draws seeded draws: plain
  expansion, a ratio estimator and regression (GREG) estimators fitted on the sampled units only,
  on features of the unit itself and summed over the rays in flight ahead of it. For each: the
  largest and rms error, the mean 95% half-interval (successive differences of the sampled
  residuals, each divided by 1 - its leverage; Student's t) and how many intervals held the truth.
  With --certain 1 the first and the last unit are always measured (the pipeline's fill and
  drain: testbench/sampling/sample_plan.h) and the strata cover the units between them. With
  --sorted
  expansion, the ratio and GREG on the replay's cycles are also measured with strata cut in the
  order of the units' replay cycles (a unit's stratum holds units of about its replay cycles).
"""
import argparse
import csv
import json
import math
import os

import numpy as np

TYPES = ("trv", "list", "ist", "shading")
R2_FEATURES = (
    "trv_reads",
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
# Student's t, 0.975 quantile, for 1..30 degrees of freedom (1.96 beyond)
T975 = (12.71, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179)
T975 += (2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064)
T975 += (2.060, 2.056, 2.052, 2.048, 2.045, 2.042)


def t975(df):
    return T975[df - 1] if 1 <= df <= len(T975) else 1.96


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


def derive(feats, hw):
    feats["leaves"] = feats["list_reads"] / 2
    for what in ("l1_misses", "dram_lines", "l1_lines"):
        feats[what] = sum(feats[t + "_" + what] for t in TYPES)
    # The cycles the L2s' banks take to send the L1 misses' lines back (a line's flits a bank),
    # the busiest L2's: a floor under a batch's cycles that the replay does not model.
    trv = "bvh" if hw.get("structure") == "bvh" else "trv"
    floors = []
    for section, misses in (
        (trv, feats["trv_l1_misses"]),
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
    trv = hw["bvh"] if hw.get("structure") == "bvh" else hw["trv"]
    in_flight = trv["count"] * (trv["capacity"] + trv["fifo_depth"])
    feats = read_phases(features_csv)
    out = {}
    for phase, cycles in ((ph, runs[ph]["cycles"]) for ph in runs):
        if int(cycles.sum()) != report["cycles_" + phase]:
            raise SystemExit(f"{run_dir}: batches.csv does not add up to cycles_{phase}")
        if phase not in feats or len(feats[phase]["batch"]) != len(cycles):
            raise SystemExit(f"{features_csv}: not the run's {len(cycles)} {phase} batches")
        f = derive(feats[phase], hw)
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


def window(x, depth):
    """The batches' feature over the rays in flight ahead of each batch: the sum over the batches
    issued depth - depth/2 .. depth + depth/2 - 1 batches earlier."""
    lo = max(1, depth - depth // 2)
    return lag_matrix(x, range(lo, lo + max(1, depth))).sum(axis=1)


def regressors(feats, g, depth, names):
    """Per unit: each named feature of the unit itself and over the rays in flight ahead of it."""
    cols = []
    for name in names:
        cols.append(to_units(feats[name], g))
        cols.append(to_units(window(feats[name], depth), g))
    return np.column_stack(cols)


def strata(n_units, f):
    k = max(1, round(1 / f))
    starts = np.arange(0, n_units, k)
    sizes = np.minimum(starts + k, n_units) - starts
    return starts, sizes


def sd_variance(t, f):
    """Successive-difference variance of a total from the per-stratum totals t (Wolter)."""
    n = len(t)
    if n < 2:
        return float("nan")
    return (1 - f) * n / (2 * (n - 1)) * float(np.sum(np.diff(t) ** 2))


def estimate(y, x, sample, sizes, f, kind):
    """The total, its variance and its degrees of freedom from the sampled units `sample` (one
    per stratum, stratum sizes `sizes`): kind "expansion", "ratio" (x one column) or "greg"."""
    w = sizes.astype(float)
    ys = y[sample]
    if kind == "expansion":
        return float(np.sum(w * ys)), sd_variance(w * ys, f), len(sample) - 1
    xs = x[sample]
    if kind == "ratio":
        r = np.sum(w * ys) / np.sum(w * xs[:, 0])
        e = ys - r * xs[:, 0]
        return float(r * x[:, 0].sum()), sd_variance(w * e, f), len(sample) - 1
    a = np.column_stack([np.ones(len(sample)), xs])
    sw = np.sqrt(w)
    aw = a * sw[:, None]
    beta, *_ = np.linalg.lstsq(aw, ys * sw, rcond=None)
    pred_all = np.column_stack([np.ones(len(y)), x]) @ beta
    e = ys - a @ beta
    total = float(pred_all.sum() + np.sum(w * e))
    # The variance from the residuals each unit would have had left out of the fit (e / (1 - h),
    # h its leverage): the fit's own residuals understate it when a few units steer the fit.
    h = np.einsum("ij,ji->i", aw, np.linalg.pinv(aw))
    e_out = e / np.maximum(1 - h, 0.05)
    return total, sd_variance(w * e_out, f), len(sample) - a.shape[1]


def draws(y, x, f, kind, n_draws, rng, certain=False, key=None):
    """Relative errors, relative half-intervals and whether each held the truth. `certain`: the
    first and the last unit are always measured, the strata cover the others. `key`: the strata
    are cut in the order of the units' key (an auxiliary), not in issue order."""
    truth = y.sum()
    known = 0.0
    if certain:
        known = y[0] + y[-1]
        y = y[1:-1]
        x = None if x is None else x[1:-1]
        key = None if key is None else key[1:-1]
    if key is not None:
        order = np.argsort(key, kind="stable")
        y = y[order]
        x = None if x is None else x[order]
    starts, sizes = strata(len(y), f)
    errs, halves, held = [], [], 0
    for _ in range(n_draws):
        sample = starts + (rng.random(len(starts)) * sizes).astype(int)
        total, var, df = estimate(y, x, sample, sizes, f, kind)
        total += known
        half = t975(max(1, df)) * math.sqrt(max(var, 0.0))
        errs.append((total - truth) / truth)
        halves.append(half / truth)
        held += abs(total - truth) <= half
    errs = np.array(errs)
    return (
        float(np.abs(errs).max()),
        float(np.sqrt(np.mean(errs**2))),
        float(np.mean(halves)),
        held,
    )


def own_and_ahead(feats, g, depth, name):
    return regressors(feats, g, depth, [name])


def estimators(phase, feats, g, depth):
    """The estimators compared: (label, kind, regressor matrix or None)."""
    if phase == "frame":
        return frame_estimators(feats, g)
    replay = to_units(feats["replay_cycles"], g)[:, None]
    ist = own_and_ahead(feats, g, depth, "ist_reads")
    both = np.column_stack([replay, ist, own_and_ahead(feats, g, depth, "l1_misses")])
    out = [
        ("expansion", "expansion", None),
        ("ratio: IST reads in flight", "ratio", ist[:, 1:2]),
        ("ratio: replay cycles", "ratio", replay),
        ("GREG: replay cycles", "greg", replay),
        ("GREG: IST reads, own + in flight", "greg", ist),
        ("GREG: replay + IST reads + L1 misses", "greg", both),
        (
            "GREG: replay + L2 floor",
            "greg",
            np.column_stack([replay, to_units(feats["l2_floor"], g)]),
        ),
    ]
    if phase == "shadow":
        rays = to_units(feats["rays"], g)[:, None]
        out.append(("GREG: replay + shadow rays", "greg", np.column_stack([replay, rays])))
    return out


def frame_estimators(feats, g):
    """The frame's: on each phase's replay cycles, and its IST reads (own + in flight)."""
    fp, dp, fs, ds = feats["phases"]
    rp = to_units(fp["replay_cycles"], g)[:, None]
    rs = to_units(fs["replay_cycles"], g)[:, None]
    ist = [own_and_ahead(fp, g, dp, "ist_reads"), own_and_ahead(fs, g, ds, "ist_reads")]
    return [
        ("expansion", "expansion", None),
        ("ratio: replay cycles", "ratio", rp + rs),
        ("GREG: replay cycles", "greg", rp + rs),
        ("GREG: each phase's replay cycles", "greg", np.column_stack([rp, rs])),
        ("GREG: each phase's replay + IST reads", "greg", np.column_stack([rp, rs] + ist)),
        (
            "GREG: replay + L2 floor",
            "greg",
            np.column_stack([rp + rs, to_units(feats["l2_floor"], g)]),
        ),
    ]


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


SORTED = ("expansion", "ratio: replay cycles", "GREG: replay cycles")


def with_sorted(ests, feats, g, sorted_too):
    """The estimators in issue-order strata and, with `sorted_too`, the SORTED ones again in
    strata cut in the order of the units' replay cycles."""
    out = [(label, kind, x, None) for label, kind, x in ests]
    if sorted_too:
        key = to_units(feats["replay_cycles"], g)
        out += [
            (label + " [strata by replay]", kind, x, key)
            for label, kind, x in ests
            if label in SORTED
        ]
    return out


def print_estimates(name, phase, cycles, feats, depth, args):
    print(f"\n## {name}, {phase}: estimates over {args.draws} draws\n")
    print(
        "| unit | fraction | certain | n | estimator | largest error | rms error "
        "| mean 95% half | held |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for g in args.units:
        y = to_units(cycles, g)
        for f in args.fractions:
            for certain in args.certain:
                n = len(strata(len(y) - 2 * certain, f)[0]) + 2 * certain
                for label, kind, x, key in with_sorted(
                    estimators(phase, feats, g, depth), feats, g, args.sorted
                ):
                    if x is not None and kind == "greg" and n < 5 * (x.shape[1] + 1):
                        continue  # too few sampled units for so many coefficients
                    rng = np.random.default_rng(args.seed)
                    worst, rms, half, held = draws(y, x, f, kind, args.draws, rng, certain, key)
                    print(
                        f"| {g} x 64 | {f:.0%} | {'yes' if certain else 'no'} | {n} | {label} "
                        f"| {worst:.2%} | {rms:.2%} | {half:.2%} | {held}/{args.draws} |"
                    )


def main():
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("pairs", nargs="+", help="RUN_DIR:FEATURES_CSV")
    p.add_argument("--draws", type=int, default=40)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--units", default="1,8,32,64")
    p.add_argument("--fractions", default="0.02,0.05,0.1")
    p.add_argument("--phases", default="primary,shadow,frame")
    p.add_argument("--certain", default="0", help="0, 1 or 0,1: first and last unit measured")
    p.add_argument("--no-r2", action="store_true", help="only the estimates")
    p.add_argument(
        "--sorted", action="store_true", help="also strata cut in order of the replay cycles"
    )
    args = p.parse_args()
    args.units = [int(u) for u in args.units.split(",")]
    args.fractions = [float(f) for f in args.fractions.split(",")]
    args.certain = [bool(int(c)) for c in args.certain.split(",")]
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
            if not args.no_r2:
                print_r2(name, phase, cycles, feats, depth, args.units)
            print_estimates(name, phase, cycles, feats, depth, args)


if __name__ == "__main__":
    main()
