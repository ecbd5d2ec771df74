"""Figures of one run directory: culled.png and plot_*.png (plots.py run)."""

import csv
import math
import os

import numpy as np

from rtsim_plots.common import (
    BUSY,
    CULLED_MAX_WIDTH,
    IDLE,
    InputError,
    STALLED,
    bar_labels,
    field,
    is_number,
    load_parsed,
    number,
    pct,
    plt,
    save,
)
from rtsim_plots.energy_figures import parse_energy, plot_energy
from rtsim_plots.files import CULLED_NPY, REPORT_JSON, SAMPLE_CSV


def report_list(rep, name, keys):
    """The report's list `name` (its unit types or its caches), each entry with `keys`."""
    entries = field(rep, name)
    ok = isinstance(entries, list) and all(
        isinstance(e, dict) and all(k in e for k in keys) for e in entries
    )
    if not ok:
        raise InputError(f"{REPORT_JSON}: field '{name}' is not a list of {{{', '.join(keys)}}}")
    return entries


def parse_units(rep, stats):
    """Per unit type the report lists, (label, busy, stalled, idle) cycles; (label, None, None,
    None) when its statistics are absent. A type summed over its units says how many."""
    units = []
    for u in report_list(rep, "units", ("key", "label", "count", "stats")):
        label, path = u["label"], u["stats"]
        if path != u["key"] and is_number(u["count"]):
            label += f" (×{u['count']:g})"
        s = field(stats, path, None)
        if isinstance(s, dict):
            where = f"{REPORT_JSON}: stats.{path}"
            states = ("busy_cycles", "stalled_cycles", "idle_cycles")
            units.append((label, *(number(s, k, where) for k in states)))
        else:
            units.append((label, None, None, None))
    return units


def parse_caches(rep, stats):
    """Per unit type with a cache the report lists, (label, [L1, L2] hit rate in %), and the DRAM
    row-hit rate; None where unknown."""

    def hit_rate(path):
        c = field(stats, path, None)
        if not isinstance(c, dict) or not is_number(c.get("hit_rate")):
            return None
        if is_number(c.get("accesses")) and c["accesses"] == 0:
            return None  # a cache nobody used reports 0, which is not a hit rate
        return 100.0 * c["hit_rate"]

    by_unit = {}  # unit key -> (label, {level: rate}), in the report's order
    for c in report_list(rep, "caches", ("key", "unit", "label", "level")):
        by_unit.setdefault(c["unit"], (c["label"], {}))[1][c["level"]] = hit_rate(c["key"])
    caches = [
        (label, [rates.get(lvl) for lvl in ("L1", "L2")]) for label, rates in by_unit.values()
    ]
    dram = field(stats, "dram.row_hit_rate", None)
    dram = 100.0 * dram if is_number(dram) else None
    return caches, dram


SAMPLED_NOTE = "sampled, 95% interval"
PHASES = (("cycles_primary", "primary"), ("cycles_shadow", "shadow"), ("cycles_total", "frame"))


def parse_sample(rep):
    """A sampled run's estimates, {key: (cycles, 95% half-interval)} per phase and the frame, with
    its fraction; None for a full run. The interval is None when the run has none (null: too few
    units drawn to estimate one)."""
    if field(rep, "sampled", False) is not True:
        return None

    def ci(k):
        v = field(rep, k + "_ci95")
        if v is not None and not is_number(v):
            raise InputError(f"{REPORT_JSON}: field '{k}_ci95' is not a number or null")
        return None if v is None else float(v)

    out = {k: (number(rep, k), ci(k)) for k, _ in PHASES}
    out["fraction"] = number(rep, "sample.fraction")
    return out


def parse_report(rep):
    """Everything the run figures need, checked up front so bad input writes no file."""
    if not isinstance(rep, dict):
        raise InputError(f"{REPORT_JSON}: not a JSON object")
    name = field(rep, "scene.name")
    res = field(rep, "scene.resolution")
    if not (
        isinstance(res, list) and len(res) == 2 and all(isinstance(v, int) and v > 0 for v in res)
    ):
        raise InputError(f"{REPORT_JSON}: field 'scene.resolution' is not [width, height]")
    lvb_on = field(rep, "config.run.lvb")
    if not isinstance(lvb_on, bool):
        raise InputError(f"{REPORT_JSON}: field 'config.run.lvb' is not a bool")
    cycles, ghz = number(rep, "cycles_total"), number(rep, "clock_ghz")

    per_light = field(rep, "per_light")
    if not isinstance(per_light, list) or not per_light:
        raise InputError(f"{REPORT_JSON}: field 'per_light' is not a non-empty list")
    rays = [
        (
            number(l, "shadow_rays", where=f"{REPORT_JSON}: per_light[{i}]"),
            number(l, "culled", where=f"{REPORT_JSON}: per_light[{i}]"),
        )
        for i, l in enumerate(per_light)
    ]
    lvb = field(rep, "lvb", None)
    leaves = None
    if lvb is not None:
        pl = field(lvb, "per_light", where=f"{REPORT_JSON}: lvb")
        if not isinstance(pl, list):
            raise InputError(f"{REPORT_JSON}: field 'lvb.per_light' is not a list")
        leaves = [
            (
                number(l, "culled_leaves", where=f"{REPORT_JSON}: lvb.per_light[{i}]"),
                number(l, "nonempty_leaves", where=f"{REPORT_JSON}: lvb.per_light[{i}]"),
            )
            for i, l in enumerate(pl)
        ]

    stats = field(rep, "stats")
    units = parse_units(rep, stats)
    caches, dram = parse_caches(rep, stats)

    sample = parse_sample(rep)
    if sample is None:
        title = f"{name} {res[0]}×{res[1]}, LVB {'on' if lvb_on else 'off'}: {cycles:,.0f} cycles"
        title += f" = {cycles / (ghz * 1e6):.4g} ms at {ghz:g} GHz" if ghz > 0 else ""
    elif sample["cycles_total"][1] is None:  # an estimate whose interval could not be had
        title = f"{name} {res[0]}×{res[1]}, LVB {'on' if lvb_on else 'off'}: {cycles:,.0f} cycles"
        title += f" = {cycles / (ghz * 1e6):.4g} ms" if ghz > 0 else ""
        title += f" ({SAMPLED_NOTE} unknown: too few units drawn)"
    else:  # an estimate: never without its interval
        ci = sample["cycles_total"][1]
        title = f"{name} {res[0]}×{res[1]}, LVB {'on' if lvb_on else 'off'}: {cycles:,.0f} ± "
        title += f"{ci:,.0f} cycles"
        title += f" = {cycles / (ghz * 1e6):.4g} ± {ci / (ghz * 1e6):.2g} ms" if ghz > 0 else ""
        title += f" ({SAMPLED_NOTE})"
    return dict(
        title=title,
        sample=sample,
        ghz=ghz,
        width=res[0],
        height=res[1],
        lvb_on=lvb_on,
        rays=rays,
        leaves=leaves,
        units=units,
        caches=caches,
        dram=dram,
        energy=parse_energy(rep),
    )


def load_culled(path, r):
    try:
        with open(path, "rb") as f:
            if f.read(6) != b"\x93NUMPY":  # else np.load would guess a pickle and say so
                raise InputError(f"{path}: not a .npy file")
        a = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as e:
        raise InputError(f"{path}: cannot read: {e}") from None
    if not isinstance(a, np.ndarray) or a.dtype != np.uint16 or a.ndim != 2:
        raise InputError(f"{path}: expected a uint16 array of shape (H, W)")
    if a.shape != (r["height"], r["width"]):
        raise InputError(
            f"{path}: shape {a.shape} does not match the resolution {r['width']}x{r['height']}"
        )
    n = len(r["rays"])
    # A bit above the last light means the file uses another layout (e.g. bit 0 = hit, bit 1+i =
    # light i).
    if n < 16 and (a >> n).any():
        raise InputError(
            f"{path}: bits set above light {n}; expected bit i = light i "
            f"for the {n} lights in report.json"
        )
    return a


def block_mean(img, f):
    """Mean over f x f pixel blocks; the last row and column of blocks may be partial."""
    if f == 1:
        return img.astype(np.float32)
    h, w = img.shape
    rows, cols = np.arange(0, h, f), np.arange(0, w, f)
    sums = np.add.reduceat(np.add.reduceat(img, rows, axis=0, dtype=np.int32), cols, axis=1)
    counts = np.outer(np.diff(np.append(rows, h)), np.diff(np.append(cols, w)))
    return (sums / counts).astype(np.float32)


def plot_culled(a, r, path, written):
    n = len(r["rays"])
    h, w = a.shape
    f = max(1, math.ceil(w / CULLED_MAX_WIDTH))
    panels, total = [], np.zeros(a.shape, np.uint8)
    for i in range(n):
        bit = ((a >> i) & 1).astype(np.uint8)
        total += bit
        panels.append((block_mean(bit, f), int(np.count_nonzero(bit))))
    ncols = min(4, n + 1)
    nrows = math.ceil((n + 1) / ncols)
    # Panel height in inches: 4-inch cells hold 3.5-inch-wide images next to the labels.
    ph = 3.5 * h / w
    fig = plt.figure(figsize=(4.0 * ncols + 0.6, nrows * (ph + 0.75) + 1.5), layout="constrained")
    # The colorbars get a row of their own: colorbars attached to panels upset the grid.
    gs = fig.add_gridspec(nrows + 1, ncols, height_ratios=[ph] * nrows + [0.12])
    axes = [fig.add_subplot(gs[k // ncols, k % ncols]) for k in range(n + 1)]
    half = (ncols + 1) // 2
    cax_lights, cax_total = fig.add_subplot(gs[nrows, :half]), fig.add_subplot(gs[nrows, half:])
    extent = (0, w, h, 0)  # axes in full-resolution pixels, row 0 at the top
    for i, (img, count) in enumerate(panels):
        im = axes[i].imshow(
            img, cmap="inferno", vmin=0, vmax=1, extent=extent, interpolation="antialiased"
        )
        axes[i].set_title(
            f"light {i + 1}: {count:,} culled ({100.0 * count / a.size:.1f} %)", fontsize=10
        )
    s = axes[n].imshow(
        block_mean(total, f),
        cmap="viridis",
        vmin=0,
        vmax=n,
        extent=extent,
        interpolation="antialiased",
    )
    axes[n].set_title(f"all lights: {int(total.sum(dtype=np.int64)):,} culled", fontsize=10)
    block = "pixel" if f == 1 else f"{f}×{f}-pixel block"
    fig.colorbar(
        im,
        cax=cax_lights,
        orientation="horizontal",
        label=f"light panels: fraction of shadow rays culled per {block}",
    )
    fig.colorbar(
        s,
        cax=cax_total,
        orientation="horizontal",
        label="all lights: culled lights per pixel" + ("" if f == 1 else " (block mean)"),
    )
    for ax in axes:
        ax.set_xlabel("x (px)")
        ax.set_ylabel("y (px)")
    fig.suptitle(
        f"{r['title']}\nshadow rays from primary hits culled by the LVB (% of all {w}×{h} pixels)"
    )
    save(fig, path, written)


def plot_culling(r, path, written):
    if not r["lvb_on"]:
        fig, ax = plt.subplots(figsize=(8, 3), layout="constrained")
        ax.set_axis_off()
        ax.text(
            0.5,
            0.5,
            "LVB culling was off in this run:\nno leaves or shadow rays were culled.",
            ha="center",
            va="center",
            fontsize=13,
        )
        fig.suptitle(r["title"])
        save(fig, path, written)
        return
    n = max(len(r["rays"]), len(r["leaves"] or []))
    leaves = [
        pct(*r["leaves"][i]) if r["leaves"] and i < len(r["leaves"]) else None for i in range(n)
    ]
    rays = [pct(r["rays"][i][1], r["rays"][i][0]) if i < len(r["rays"]) else None for i in range(n)]
    x, bw = np.arange(n), 0.38
    fig, ax = plt.subplots(figsize=(max(7.5, 0.9 * n + 3.0), 4.8), layout="constrained")
    ax.bar(
        x - bw / 2,
        [v or 0 for v in leaves],
        bw,
        label="leaves culled (% of non-empty leaves)",
        color="tab:blue",
    )
    ax.bar(
        x + bw / 2,
        [v or 0 for v in rays],
        bw,
        label="shadow rays culled (% of shadow rays)",
        color="tab:red",
    )
    bar_labels(ax, x - bw / 2, leaves)
    bar_labels(ax, x + bw / 2, rays)
    ax.set_xticks(x, [f"L{i + 1}" for i in range(n)])
    ax.set_xlabel("light")
    ax.set_ylabel("culled (%)")
    # Over 100 % is wrong, but show it.
    top = max([100.0] + [v for v in leaves + rays if v is not None])
    ax.set_ylim(0, 1.25 * top)  # headroom for the value labels and the legend
    ax.set_yticks(range(0, int(top) + 1, 20))
    ax.legend(loc="upper center", ncol=2, fontsize=9, frameon=False)
    ax.grid(axis="y", alpha=0.3)
    shadow, culled = sum(s for s, _ in r["rays"]), sum(c for _, c in r["rays"])
    overall = pct(culled, shadow)
    ax.set_title(
        f"{r['title']}\nLVB culling per light"
        + (
            f" (all lights: {overall:.1f} % of {shadow:,.0f} shadow rays culled)"
            if overall is not None
            else ""
        ),
        fontsize=10,
    )
    save(fig, path, written)


def plot_time_breakdown(r, path, written):
    units = r["units"]
    fig, ax = plt.subplots(figsize=(9, 0.55 * len(units) + 2.2), layout="constrained")
    y = np.arange(len(units))
    legend_done = set()  # label each state once, whichever unit draws it first
    for yi, (label, *cycles) in zip(y, units):
        total = sum(cycles) if cycles[0] is not None else 0
        if total <= 0:
            ax.text(1, yi, "n/a", va="center", fontsize=9, color="dimgray")
            continue
        left = 0.0
        for c, colour, name in zip(cycles, (BUSY, STALLED, IDLE), ("busy", "stalled", "idle")):
            share = 100.0 * c / total
            ax.barh(yi, share, left=left, color=colour, label=None if name in legend_done else name)
            legend_done.add(name)
            if share >= 4:  # narrower segments have no room for a label
                ax.text(
                    left + share / 2, yi, f"{share:.0f} %", ha="center", va="center", fontsize=8
                )
            left += share
    ax.set_yticks(y, [u[0] for u in units])
    ax.invert_yaxis()  # pipeline order from the top
    ax.set_xlim(0, 100)
    ax.set_xlabel("share of unit cycles (%), summed over the units of a type")
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=3, fontsize=9, frameon=False)
    windows = " (the sampled frame's detailed windows)" if r["sample"] else ""
    fig.suptitle(f"{r['title']}\nunit time breakdown{windows}", fontsize=10)
    save(fig, path, written)


def plot_cache_hit_rates(r, path, written):
    caches = r["caches"]
    x, bw = np.arange(len(caches)), 0.38
    fig, ax = plt.subplots(figsize=(8, 4.8), layout="constrained")
    for k, (lvl, colour) in enumerate([("L1", "tab:blue"), ("L2", "tab:purple")]):
        xs = x + (k - 0.5) * bw
        vals = [c[1][k] for c in caches]
        ax.bar(xs, [v or 0 for v in vals], bw, label=lvl, color=colour)
        bar_labels(ax, xs, vals)
    xd = len(caches) + 0.2  # DRAM is a different kind of rate: set apart from the caches
    ax.bar([xd], [r["dram"] or 0], bw, label="DRAM row hits", color="tab:gray")
    bar_labels(ax, [xd], [r["dram"]])
    ax.axvline(len(caches) - 0.4, color="black", lw=0.5, alpha=0.4)
    ax.set_xticks(list(x) + [xd], [c[0] for c in caches] + ["DRAM"])
    ax.set_xlabel("unit type (cache) / DRAM")
    ax.set_ylabel("hit rate (%)")
    ax.set_ylim(0, 125)
    ax.set_yticks(range(0, 101, 20))
    ax.grid(axis="y", alpha=0.3)
    ax.legend(loc="upper center", ncol=3, fontsize=9, frameon=False)
    ax.set_title(f"{r['title']}\ncache hit rates (n/a: no such cache or no accesses)", fontsize=10)
    save(fig, path, written)


def load_units(path):
    """sample.csv: per measured unit, (first ray, primary cycles, shadow cycles)."""
    try:
        with open(path, encoding="utf-8", newline="") as f:
            rows = list(csv.DictReader(f))
        return [
            (float(u["first_ray"]), float(u["primary_cycles"]), float(u["shadow_cycles"]))
            for u in rows
        ]
    except (KeyError, TypeError, ValueError) as e:
        raise InputError(f"{path}: not a sample.csv ({e})") from None


def plot_sample(r, units, path, written):
    """A sampled run: each phase's estimate with its 95% interval as error bars, and each measured
    unit's cycles by its first ray (sample.csv), the sample the estimates come from."""
    s = r["sample"]
    fig, axes = plt.subplots(1, 2 if units else 1, figsize=(12 if units else 6, 4.8), squeeze=False)
    ax = axes[0][0]
    x = np.arange(len(PHASES))
    est, known = [s[k][0] for k, _ in PHASES], [s[k][1] for k, _ in PHASES]
    ci = [e or 0 for e in known]  # an unknown interval (too few units drawn) says so in its label
    ax.bar(x, est, 0.6, yerr=ci, capsize=6, color="tab:blue", label=f"estimate ({SAMPLED_NOTE})")
    for xi, v, e, k in zip(x, est, ci, known):
        ax.annotate(
            f"{v:,.0f}\n± {e:,.0f}" if k is not None else f"{v:,.0f}\n± ? (too few units)",
            (xi, v + e),
            xytext=(0, 3),
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize=8,
        )
    ax.set_xticks(x, [label for _, label in PHASES])
    ax.set_ylabel("cycles")
    ax.set_ylim(0, 1.25 * max(v + e for v, e in zip(est, ci)) or 1)
    ax.legend(loc="upper left", fontsize=9, frameon=False)
    ax.grid(axis="y", alpha=0.3)
    ax.set_title(f"cycles per phase, {100 * s['fraction']:g} % of the frame's units", fontsize=10)
    if units:
        ax = axes[0][1]
        for k, (label, colour) in enumerate((("primary", "tab:orange"), ("shadow", "tab:green"))):
            ax.plot([u[0] for u in units], [u[1 + k] for u in units], "o", ms=3, color=colour)
            ax.lines[-1].set_label(label)
        ax.set_xlabel("the unit's first ray (issue order)")
        ax.set_ylabel("cycles of the unit")
        ax.legend(fontsize=9, frameon=False)
        ax.grid(alpha=0.3)
        ax.set_title(f"the {len(units)} measured units (sample.csv)", fontsize=10)
    fig.suptitle(f"{r['title']}\nthe sampled frame", fontsize=10)
    fig.tight_layout()
    save(fig, path, written)


def run(folder, written):
    r = load_parsed(folder, REPORT_JSON, parse_report)
    npy = os.path.join(folder, CULLED_NPY)
    culled = load_culled(npy, r) if os.path.exists(npy) else None
    units, csv_path = [], os.path.join(folder, SAMPLE_CSV)
    if r["sample"] is not None and os.path.exists(csv_path):
        units = load_units(csv_path)  # read up front: bad input writes no figure
    if culled is not None:
        plot_culled(culled, r, os.path.join(folder, "culled.png"), written)
    plot_culling(r, os.path.join(folder, "plot_culling.png"), written)
    plot_time_breakdown(r, os.path.join(folder, "plot_time_breakdown.png"), written)
    plot_cache_hit_rates(r, os.path.join(folder, "plot_cache_hit_rates.png"), written)
    if r["energy"] is not None:
        plot_energy(r, r["energy"], os.path.join(folder, "plot_energy.png"), written)
    if r["sample"] is not None:
        plot_sample(r, units, os.path.join(folder, "plot_sample.png"), written)
