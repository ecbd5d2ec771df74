#!/usr/bin/env python3
"""A sampled run's estimator on a full run's true unit cycles (docs/sampling.md): the plan of
testbench/sampling/sample_plan.cpp (first and last unit always measured, one unit drawn per stratum
of round(1/F) units) and the estimators of testbench/sampling/sample_regression.cpp (GREG on the
functional pass's features; the 95% interval from the delete-one jackknife of each phase's total,
the frame's from the sums of both phases' replicates, with Satterthwaite's degrees of freedom), over
many seeds, as if every drawn unit were measured exactly: the bound that the estimator puts on a
sampled run, whatever its warming. Beside the run's estimator, the variants it was chosen from, and
plans with a take-all stratum: the m units ranked highest by an auxiliary known before the
simulation always measured (exactly, as the first and last are), the rest of the same budget of
measured units drawn one a stratum over the other units, in strata of equal size or of equal N_h S_h
of the auxiliary (Neyman's allocation with one draw a stratum). With --steps, the walk steps that a
run's Neyman strata are cut on rank units too.
  bench_sampling_features --config RUN/config.json --out features.csv [--walk-steps steps.csv]
  /usr/bin/python3 bench/sampling_plan_study.py RUN features.csv [--fraction 0.05] [--seeds 200]
      [--variants 'all'|'run'|'take-all'|'NAME;...'] [--steps steps.csv] [--auxiliary walks]

--auxiliary walks regresses on what the reference tracer's walks count without caches or replay
(a pass as cheap as the functional frame): the primary phase on its IST, TRV and LIST reads and
the IST and TRV reads of the batches in flight ahead, the shadow phase on its IST reads.

RUN: a full run's directory (batches.csv with the phase column). Prints, per variant and phase
(primary, shadow, frame), the largest, rms and 95th-percentile error, the mean 95% half-interval
and how many intervals held the truth.
"""
import argparse
import csv

import numpy as np

T975 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179]
T975 += [2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064]
T975 += [2.060, 2.056, 2.052, 2.048, 2.045, 2.042]
UNIT = 32  # batches of 64 rays: run.sample_unit 2,048
IN_FLIGHT = 12  # batches: the traversal units' rays (24 x (16 + 16)) over 64
RUNS = [0, 1, 2, 3, 4]  # the run's primary auxiliaries: replay, IST reads and L1 misses (+ ahead)

# name: primary columns (None: expansion), fit ("ols", "huber", "inverse": weights 1/replay),
# interval ("sd", "hc2", "pairs", "jk", "jk-satt3", "jk-satt", "model"), strata ("issue", "sorted",
# or ("take-all", ranking, m, allocation): see TAKE_ALL).
VARIANTS = {
    "expansion": (None, "ols", "sd", "issue"),
    "successive differences (the run's before)": (RUNS, "ols", "sd", "issue"),
    "successive differences, primary on replay": ([0], "ols", "sd", "issue"),
    "successive differences, primary on replay and IST reads": ([0, 1, 2], "ols", "sd", "issue"),
    "successive differences of e / sqrt(1 - h) (HC2)": (RUNS, "ols", "hc2", "issue"),
    "collapsed strata pairs, t for n / 2": (RUNS, "ols", "pairs", "issue"),
    "jackknife, t for n - p": (RUNS, "ols", "jk", "issue"),
    "jackknife, primary on replay": ([0], "ols", "jk", "issue"),
    "jackknife, Satterthwaite's degrees of freedom (the run's)": (RUNS, "ols", "jk-satt3", "issue"),
    "jackknife, Satterthwaite's degrees of freedom, d^4 plug-in": (RUNS, "ols", "jk-satt", "issue"),
    "Huber-weighted fit, successive differences": (RUNS, "huber", "sd", "issue"),
    "fit weighted 1 / replay, jackknife": (RUNS, "inverse", "jk", "issue"),
    "larger of successive differences and e^2 ratio-estimated on replay": (
        RUNS,
        "ols",
        "model",
        "issue",
    ),
    "strata sorted by replay (a plan change), successive differences": (
        RUNS,
        "ols",
        "sd",
        "sorted",
    ),
}


# The rankings of a take-all stratum, cheapest first: (a) known from a primary walk and the LVB
# bits, (b) the functional pass's primary phase, (c) the whole pass (before the simulation).
RANKINGS = {
    "(a) shadow rays": "shadow_rays",
    "(a) primary hits": "hits",
    "(a) shadow rays + hits": "rays_hits",
    "(a) IST reads of both phases": "ist_reads",
    "(a) every unit's reads of both phases": "reads",
    "(a) walk steps, culling off (--steps)": "walk_steps",
    "(b) primary replay": "primary_replay",
    "(a)x(b) primary replay x (1 + shadow rays / unit)": "primary_replay_rays",
    "(c) both replays": "replay",
    "(c') both replays, shadow on 1 batch in 4": "replay_stride4",
    "(c') both replays, shadow on 1 batch in 8": "replay_stride8",
}
THE_RUN = (RUNS, "ols", "jk-satt3", "issue")  # the run's estimator and plan
TAKE_ALL = {"current plan (baseline)": THE_RUN}
for _rank, _key in RANKINGS.items():
    for _m in (
        (5, 10, 20)
        if _key in ("shadow_rays", "hits", "rays_hits", "primary_replay", "replay")
        else ()
    ):
        TAKE_ALL[f"take-all {_m}, {_rank}"] = THE_RUN[:3] + (("take-all", _key, _m, "equal"),)
for _rank, _key in RANKINGS.items():
    if _key != "hits":
        TAKE_ALL[f"Neyman strata, {_rank}"] = THE_RUN[:3] + (("take-all", _key, 0, "neyman"),)
        TAKE_ALL[f"take-all 10 + Neyman strata, {_rank}"] = THE_RUN[:3] + (
            ("take-all", _key, 10, "neyman"),
        )
for _rank, _key in RANKINGS.items():
    if _key not in ("hits", "rays_hits"):
        TAKE_ALL[f"strata of equal totals, {_rank}"] = THE_RUN[:3] + (
            ("take-all", _key, 0, "total"),
        )


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


def load(run, features, steps=None, auxiliary="pass"):
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
    if auxiliary == "walks":  # what the walks alone count: no caches, no replay
        reads = [p[f"{t}_reads"] for t in ("ist", "trv", "list")]
        xp = np.column_stack([units(r) for r in reads] + [units(ahead(r)) for r in reads[:2]])
        xs = units(feat["shadow"]["ist_reads"])[:, None]
    rays, hits = units(feat["shadow"]["rays"]), units(p["hits"])
    keys = {  # the rankings of a take-all stratum (RANKINGS), per unit
        "shadow_rays": rays,
        "hits": hits,
        "rays_hits": rays / max(rays.mean(), 1.0) + hits / max(hits.mean(), 1.0),
        "primary_replay": xp[:, 0],
        "primary_replay_rays": xp[:, 0] * (1 + rays / (UNIT * 64)),
        "replay": xp[:, 0] + xs[:, 0],
        "ist_reads": units(p["ist_reads"] + feat["shadow"]["ist_reads"]),
        "reads": sum(
            units(p[f"{t}_reads"] + feat["shadow"][f"{t}_reads"]) for t in ("trv", "list", "ist")
        ),
    }
    if steps:  # bench_sampling_features --walk-steps: per primary batch
        with open(steps, newline="") as f:
            keys["walk_steps"] = units([float(r["walk_steps"]) for r in csv.DictReader(f)])
    for k in (4, 8):  # a pass with shadow_stride k, approximated: its batches of the full pass's
        every = feat["shadow"]["replay_cycles"] * (np.arange(len(feat["shadow"]["rays"])) % k == 0)
        keys[f"replay_stride{k}"] = xp[:, 0] + k * units(every)
    return units(y["primary"]), units(y["shadow"]), xp, xs, keys


def strata_of(n_units, fraction, order=None):
    """testbench/sampling/sample_plan.cpp's strata: k = round(1 / F) consecutive units of `order`
    (the
    units between the first and the last in issue order if not given)."""
    k = max(1, round(1 / fraction))
    inner = np.arange(1, n_units - 1) if order is None else order
    return [inner[first : first + k] for first in range(0, len(inner), k)]


def cut_strata(key, rest, count, allocation):
    """`count` strata of consecutive units of `rest` (issue order) with about equal N_h S_h of
    `key` ("neyman": Neyman's allocation n_h ~ N_h S_h with one draw a stratum) or equal sums of
    it ("total": n_h ~ the stratum's total, for residuals that grow with the auxiliary): the
    greedy cut at the bisected bound, the largest strata halved if it leaves fewer."""
    v = key[rest].astype(float)
    c1, c2 = np.concatenate([[0.0], np.cumsum(v)]), np.concatenate([[0.0], np.cumsum(v * v)])

    def measure(first, last):  # of units first .. last - 1
        n, s1 = last - first, c1[last] - c1[first]
        if allocation == "total":
            return s1
        return n * np.sqrt(max(0.0, (c2[last] - c2[first]) / n - (s1 / n) ** 2))

    def cut(bound):
        out, first = [], 0
        for last in range(1, len(v) + 1):
            if last == len(v) or measure(first, last + 1) > bound:
                out.append((first, last))
                first = last
        return out

    lo, hi = 0.0, measure(0, len(v)) + 1.0
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if len(cut(mid)) > count else (lo, mid)
    out = cut(hi)
    while len(out) < count:
        i = max(range(len(out)), key=lambda j: out[j][1] - out[j][0])
        a, b = out[i]
        out[i : i + 1] = [(a, (a + b) // 2), ((a + b) // 2, b)]
    return [rest[a:b] for a, b in out]


def take_all_strata(n_units, fraction, key, m, allocation):
    """The always-measured units (the first, the last and the m others ranked highest by `key`)
    and the strata of the rest: as many as the current plan draws less m (the same number of
    measured units), of equal size or by Neyman's allocation."""
    inner = np.arange(1, n_units - 1)
    top = inner[np.argsort(-key[inner], kind="stable")[:m]]
    rest = np.setdiff1d(inner, top)
    count = len(strata_of(n_units, fraction)) - m
    if allocation in ("neyman", "total"):
        return sorted(top), cut_strata(key, rest, count, allocation)
    return sorted(top), np.array_split(rest, count)


def plan(n_units, seed, strata, certain=()):
    """(unit, weight, certain) as testbench/sampling/sample_plan.cpp: the first and the last unit
    and
    `certain` always measured, one unit drawn at random from each stratum."""
    rng = np.random.default_rng(seed)
    out = [(0, 1, True)] + [(int(u), 1, True) for u in certain]
    for s in strata:
        out.append((int(s[int(rng.integers(len(s)))]), len(s), False))
    return out + [(n_units - 1, 1, True)]


def solve(ad, y, w):
    m = ad.T @ (w[:, None] * ad)
    try:
        return np.linalg.solve(m, ad.T @ (w * y)), m
    except np.linalg.LinAlgError:
        return None, m


def fit(y, ad, w, how, x0):
    """The coefficients and the fit's weights per drawn unit (OLS, Huber's or 1 / replay)."""
    u = 1.0 / np.maximum(x0, 1.0) if how == "inverse" else np.ones(len(y))
    beta, m = solve(ad, y, w * u)
    for _ in range(20 if how == "huber" else 0):  # IRLS, Huber's k = 1.345 times the MAD's scale
        e = y - ad @ beta
        s = 1.4826 * np.median(np.abs(e - np.median(e))) + 1e-9
        z = np.abs(e) / (1.345 * s)
        u = np.where(z <= 1, 1.0, 1.0 / np.maximum(z, 1e-12))
        beta, m = solve(ad, y, w * u)
    return beta, m, u


def greg(y, x, sample, cols, how="ols", jackknife=False):
    """testbench/sampling/sample_regression.cpp's estimate_greg: the total, the drawn units'
    weighted
    residuals over 1 - their leverage, their leverages, and (jackknife) their replicates' deviations
    (estimate_plan's for the expansion, cols None)."""
    cert = [i for i, _, c in sample if c]
    idx = np.array([i for i, _, c in sample if not c])
    w = np.array([float(s) for _, s, c in sample if not c])
    big_w = w.sum()
    if cols is None:
        t = np.sum(w * y[idx])
        dev = big_w / (big_w - w) * (t - w * y[idx]) - t
        return y[cert].sum() + t, w * y[idx], np.zeros(len(idx)), dev, 1
    a = np.column_stack([np.ones(len(y)), x[:, cols]])
    a = a / np.abs(a).mean(axis=0)
    ad = a[idx]
    rest = np.ones(len(y), bool)
    rest[cert] = False
    rest_sum = a[rest].sum(axis=0)
    beta, m, u = fit(y[idx], ad, w, how, x[idx, 0])
    full = rest_sum @ beta + np.sum(w * (y[idx] - ad @ beta))
    e = y[idx] - ad @ beta
    lev = w * u * np.einsum("ij,jk,ik->i", ad, np.linalg.inv(m), ad)
    dev = np.zeros(len(idx))
    for i in range(len(idx) if jackknife else 0):
        wi = w * big_w / (big_w - w[i])
        wi[i] = 0.0
        bi = fit(y[idx], ad, wi, how, x[idx, 0])[0]
        bi = beta if bi is None else bi
        dev[i] = rest_sum @ bi + np.sum(wi * (y[idx] - ad @ bi)) - full
    return y[cert].sum() + full, w * e / np.maximum(1 - lev, 0.05), lev, dev, a.shape[1]


def half_interval(kind, r, dof, fpc, v_model=None):
    """The 95% half-interval of a total from its drawn units' residuals or deviations `r`."""
    n = len(r)
    if kind in ("sd", "hc2", "model"):
        v = fpc * n * np.sum(np.diff(r) ** 2) / (2 * (n - 1))
        return t95(dof) * np.sqrt(max(v, v_model) if kind == "model" else v)
    if kind == "pairs":  # strata collapsed in pairs; an odd one out with its left neighbour
        m = n // 2
        v = np.sum((r[0 : 2 * m : 2] - r[1 : 2 * m : 2]) ** 2)
        v += (r[-1] - r[-2]) ** 2 / 2 if n % 2 else 0
        return t95(m) * np.sqrt(fpc * v)
    d = r - r.mean()  # the jackknife
    if kind.startswith("jk-satt"):  # Satterthwaite's degrees of freedom of a sum of squares
        c = 3.0 if kind == "jk-satt3" else 1.0  # the run's: E d^4 = 3 (E d^2)^2 for a normal d
        dof = int(max(1, min(dof, c * np.sum(d**2) ** 2 / max(np.sum(d**4), 1e-300))))
    return t95(dof) * np.sqrt(fpc * (n - 1) / n * np.sum(d**2))


def model_variance(r, sample, x0):
    """The population's sum of squared unit residuals, ratio-estimated on the replay's cycles
    (known for every unit), times k - 1: the stratified design's variance if a unit's residual
    variance grew with its replay cycles."""
    idx = np.array([i for i, _, c in sample if not c])
    w = np.array([float(s) for _, s, c in sample if not c])
    rest = np.ones(len(x0), bool)
    rest[[i for i, _, c in sample if c]] = False
    k = w.sum() / len(w)
    v = np.maximum(x0, 1.0)
    return (k - 1) * v[rest].sum() * np.sum(w * (r / w) ** 2) / np.sum(w * v[idx])


def design(data, strata, fraction):
    """A variant's plan: the units always measured beside the first and last, and the strata."""
    yp, xp, xs, keys = data[0], data[2], data[3], data[4]
    if strata == "sorted":
        key = xp[1:-1, 0] + xs[1:-1, 0]
        return (), strata_of(len(yp), fraction, 1 + np.argsort(key, kind="stable"))
    if strata == "issue":
        return (), strata_of(len(yp), fraction)
    _, key, m, allocation = strata
    return take_all_strata(len(yp), fraction, keys[key], m, allocation)


def one_draw(data, variant, fraction, seed, plan_design=None):
    """Each phase's and the frame's (estimate, 95% half-interval) for one seed's sample."""
    yp, ys, xp, xs = data[:4]
    cols, how, kind, strata = variant
    certain, cells = plan_design or design(data, strata, fraction)
    sample = plan(len(yp), seed, cells, certain)
    jk = kind.startswith("jk")
    tp, rp, hp, dp, p = greg(yp, xp, sample, cols, how, jk)
    ts, rs, hs, ds, q = greg(ys, xs, sample, None if cols is None else [0], how, jk)
    w = np.array([float(s) for _, s, c in sample if not c])
    n = len(w)
    fpc = 1 - n / w.sum()
    if kind == "hc2":  # e / sqrt(1 - h) instead of e / (1 - h)
        rp = rp * np.sqrt(np.maximum(1 - hp, 0.05))
        rs = rs * np.sqrt(np.maximum(1 - hs, 0.05))
    if jk or cols is None:
        rp, rs = (dp, ds) if jk else (rp, rs)
    out = {}
    for ph, t, r, dof, x0 in (
        ("primary", tp, rp, n - p, xp[:, 0]),
        ("shadow", ts, rs, n - q, xs[:, 0]),
        ("frame", tp + ts, rp + rs, n - max(p, q), xp[:, 0] + xs[:, 0]),
    ):
        vm = model_variance(r, sample, x0) if kind == "model" else None
        out[ph] = (t, half_interval(kind, r, dof, fpc, vm))
    return out


def study(data, variant, fraction, seeds):
    """Per phase: the relative errors, the relative half-intervals and the intervals that held."""
    yp, ys = data[0], data[1]
    truth = {"primary": yp.sum(), "shadow": ys.sum(), "frame": yp.sum() + ys.sum()}
    res = {ph: ([], [], 0) for ph in truth}
    plan_design = design(data, variant[3], fraction)
    for seed in range(1, seeds + 1):
        for ph, (t, h) in one_draw(data, variant, fraction, seed, plan_design).items():
            errs, halves, held = res[ph]
            errs.append(abs(t - truth[ph]) / truth[ph])
            halves.append(h / truth[ph])
            res[ph] = (errs, halves, held + (abs(t - truth[ph]) <= h))
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("features")
    ap.add_argument("--fraction", type=float, default=0.05)
    ap.add_argument("--seeds", type=int, default=200)
    ap.add_argument("--steps", help="bench_sampling_features --walk-steps output")
    ap.add_argument("--variants", default="all", help="all, run, take-all or names joined by ';'")
    ap.add_argument(
        "--auxiliary",
        choices=("pass", "walks"),
        default="pass",
        help="regress on the pass's features (the run's) or on the walks' reads alone",
    )
    a = ap.parse_args()
    data = load(a.run, a.features, a.steps, a.auxiliary)
    variants = {**VARIANTS, **TAKE_ALL}
    names = list(VARIANTS)
    if a.variants == "run":
        names = ["expansion", "jackknife, Satterthwaite's degrees of freedom (the run's)"]
    elif a.variants == "take-all":
        names = list(TAKE_ALL)
    elif a.variants != "all":
        names = a.variants.split(";")
    print(f"{a.run}: {len(data[0])} units, fraction {a.fraction}, {a.seeds} seeds")
    print("| variant | phase | largest | rms | 95th percentile | mean 95% interval | held |")
    print("|---|---|---|---|---|---|---|")
    for name in names:
        for ph, (errs, halves, held) in study(data, variants[name], a.fraction, a.seeds).items():
            e = np.array(errs)
            print(
                f"| {name} | {ph} | {100 * e.max():.2f}% | {100 * np.sqrt(np.mean(e**2)):.2f}% | "
                f"{100 * np.percentile(e, 95):.2f}% | {100 * np.mean(halves):.2f}% | "
                f"{held} of {a.seeds} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
