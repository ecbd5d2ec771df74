#!/usr/bin/python3
"""PNG figures for an rtsim run, sweep or reproduce directory.

Usage:
    plots.py run DIR [--verbose]
    plots.py sweep DIR [--verbose]
    plots.py reproduce DIR [--verbose]
    plots.py animate DIR [--verbose]
    plots.py area DIR [--verbose]

run DIR reads DIR/report.json (and DIR/culled.npy when present) and writes:
  culled.png                where shadow rays were culled: one panel per light (fraction of pixels culled
                            per block, all on one colour scale; the % in its title is of all pixels) and one
                            "all lights" panel (culled lights per pixel). culled.npy is uint16 (H, W), bit i =
                            the primary hit's shadow ray to light i was culled. Skipped when it is absent.
  plot_culling.png          the paper's Fig. 7: per light, % of non-empty leaves culled and % of shadow rays
                            culled. With culling off (config.run.lvb false, lvb null) the figure is still
                            written and only says so, so every run directory gets the same plot_*.png files.
                            Culling on but lvb null: the leaf bars show n/a.
  plot_time_breakdown.png   busy / stalled / idle as % of the unit cycles per unit type (summed over units).
  plot_cache_hit_rates.png  hit rate per unit type and cache level, and the DRAM row-hit rate.

sweep DIR reads DIR/results.json (schema rtsim-sweep/1) and writes DIR/plots/<metric>_vs_<axis>.png for
every metric and every axis with at least 2 distinct values (the scene counts as an axis when there are
several), plus DIR/plots/index.md listing them.

reproduce DIR reads DIR/reproduction.json (schema rtsim-reproduction/1, written by `rtsim reproduce`) and writes:
  reproduce_culling.png     per scene and light, % of shadow rays culled and % of leaves culled: the paper's
                            figures, ours with the paper's method, ours exact. Lights go by index (the paper's
                            lights are not ours, and their counts may differ). The leaf denominators differ: the
                            paper's are all leaves, ours the non-empty leaves.
  reproduce_time.png        per scene, the frame-time reduction with culling ((off - on) / off) for all rays and
                            for the shadow rays, paper vs ours; the absolute times are in the captions only.
A scene without the paper's figures, or without one of our runs, shows n/a in those places.

area DIR reads the results.json of a sweep with the axes scene.lights.area_from_points.samples and run.lvb
(configs/sweeps/area-lights.yaml) and writes, per scene and sample count, culling off against on:
  area_lights.md                   cycles off and on, the reduction (off - on) / off, shadow rays traced and culled;
                                   then, from the points' report.json, what bounds the shadow phase (TRV and IST
                                   operations culling removes, TRV idle share and IST L1 hit rate with culling off).
  plots/area_reduction.png         the frame-time reduction against the samples per light, one line per scene.

animate DIR reads DIR/frames.csv and DIR/host.csv (written by `rtsim animate`) and writes, over the scene's time:
  plots/animate_cycles.png         cycles per frame with culling off and on.
  plots/animate_culled.png         % of shadow rays culled and % of (non-empty leaf, light) bits that are 0.
  plots/animate_preprocessing.png  host seconds of the kd-tree and the LVB per frame, and the LVB's work counts
                                   (kd-tree nodes visited, region tests, pair tests).
  frames.gif                       DIR/frames/frame_NNNN.png as an animated GIF (Pillow), at the scene's pace.
  summary.md                       per frame and as medians: cycles culling saves, what rebuilding the LVB costs
                                   (host seconds; tests, as a hardware builder's cycles at one test per cycle) and
                                   what a lazy rebuild would redo (docs/animation.md).

Exit status 0 on success (silent unless --verbose, which lists the files written); on bad input one line
"plots.py: error: ..." on stderr and exit status 2. Needs only numpy and matplotlib.
"""

import argparse
import csv
import json
import math
import os
import re
import sys
import textwrap

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)
from matplotlib.ticker import NullLocator  # noqa: E402

DPI = 100
CULLED_MAX_WIDTH = 480  # panels wider than this are block-averaged: keeps culled.png small and fast
MAX_SERIES = 8  # lines per sweep plot; more are unreadable
BUSY, STALLED, IDLE = "tab:green", "tab:orange", "lightgray"


class InputError(Exception):
    """Bad input: reported as one line and exit status 2."""


_MISSING = object()


def is_number(v):
    # bool is an int subclass in Python but never a number in our JSON.
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def field(obj, path, default=_MISSING, where="report.json"):
    """obj["a"]["b"]... for path "a.b..."; default (or an InputError) when a level is missing."""
    node = obj
    for key in path.split("."):
        if not isinstance(node, dict) or key not in node:
            if default is _MISSING:
                raise InputError(f"{where}: missing field '{path}'")
            return default
        node = node[key]
    return node


def number(obj, path, where="report.json"):
    v = field(obj, path, where=where)
    if not is_number(v):
        raise InputError(f"{where}: field '{path}' is not a number")
    return float(v)


def load_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except FileNotFoundError:
        raise InputError(f"{path}: not found") from None
    except (OSError, ValueError) as e:
        raise InputError(f"{path}: {e}") from None


def load_parsed(folder, name, parse):
    """Reads folder/name and parses it; the parser's messages name the bare file, so name the real one."""
    path = os.path.join(folder, name)
    try:
        return parse(load_json(path))
    except InputError as e:
        raise InputError(str(e).replace(name, path, 1)) from None


def write_atomically(path, write, written):
    """write(tmp) writes the file under a temporary name in the same directory, which then replaces path."""
    folder, name = os.path.split(path)
    tmp = os.path.join(folder, f".{name}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
    written.append(path)


def save(fig, path, written):
    try:
        # No Software tag: the bytes should not depend on the matplotlib version.
        write_atomically(path, lambda tmp: fig.savefig(tmp, format="png", dpi=DPI, metadata={"Software": None}),
                         written)
    finally:
        plt.close(fig)


def write_text(path, text, written):
    def write(tmp):
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
    write_atomically(path, write, written)


def bar_labels(ax, xs, values, fmt="{:.1f}"):
    """Value above each bar; "n/a" where the value is unknown (None)."""
    for x, v in zip(xs, values):
        if v is None:
            ax.text(x, 1, "n/a", ha="center", va="bottom", fontsize=8, color="dimgray", rotation=90)
        else:
            ax.text(x, v + 1, fmt.format(v), ha="center", va="bottom", fontsize=8)


def pct(part, whole):
    return 100.0 * part / whole if whole > 0 else None


# ----------------------------------------------------------------------------------------------- run


def parse_report(rep):
    """Everything the run figures need, checked up front so bad input writes no file."""
    if not isinstance(rep, dict):
        raise InputError("report.json: not a JSON object")
    name = field(rep, "scene.name")
    res = field(rep, "scene.resolution")
    if not (isinstance(res, list) and len(res) == 2 and all(isinstance(v, int) and v > 0 for v in res)):
        raise InputError("report.json: field 'scene.resolution' is not [width, height]")
    lvb_on = field(rep, "config.run.lvb")
    if not isinstance(lvb_on, bool):
        raise InputError("report.json: field 'config.run.lvb' is not a bool")
    cycles, ghz = number(rep, "cycles_total"), number(rep, "clock_ghz")

    per_light = field(rep, "per_light")
    if not isinstance(per_light, list) or not per_light:
        raise InputError("report.json: field 'per_light' is not a non-empty list")
    rays = [(number(l, "shadow_rays", where=f"report.json: per_light[{i}]"),
             number(l, "culled", where=f"report.json: per_light[{i}]")) for i, l in enumerate(per_light)]
    lvb = field(rep, "lvb", None)
    leaves = None
    if lvb is not None:
        pl = field(lvb, "per_light", where="report.json: lvb")
        if not isinstance(pl, list):
            raise InputError("report.json: field 'lvb.per_light' is not a list")
        leaves = [(number(l, "culled_leaves", where=f"report.json: lvb.per_light[{i}]"),
                   number(l, "nonempty_leaves", where=f"report.json: lvb.per_light[{i}]")) for i, l in enumerate(pl)]

    stats = field(rep, "stats")
    hw = field(rep, "config.hw", {})
    units = []  # (label, busy, stalled, idle) or (label, None...) when the unit type is absent
    for label, path, count_path in [("raygen", "raygen", None), ("TRV", "trv.total", "trv.count"),
                                    ("LIST", "list.total", "list.count"), ("IST", "ist.total", "ist.count"),
                                    ("shading", "shading.total", "shading.count"), ("culling", "culling", None)]:
        s = field(stats, path, None)
        count = field(hw, count_path, None) if count_path else None
        if is_number(count):
            label += f" (×{count:g})"
        if isinstance(s, dict):
            where = f"report.json: stats.{path}"
            units.append((label, *(number(s, k, where) for k in ("busy_cycles", "stalled_cycles", "idle_cycles"))))
        else:
            units.append((label, None, None, None))

    def hit_rate(path):
        c = field(stats, path, None)
        if not isinstance(c, dict) or not is_number(c.get("hit_rate")):
            return None
        if is_number(c.get("accesses")) and c["accesses"] == 0:
            return None  # a cache nobody used reports 0, which is not a hit rate
        return 100.0 * c["hit_rate"]

    caches = [(t, [hit_rate(f"{key}.{lvl}") for lvl in ("l1", "l2")])
              for t, key in [("TRV", "trv"), ("LIST", "list"), ("IST", "ist"), ("shading", "shading")]]
    dram = field(stats, "dram.row_hit_rate", None)
    dram = 100.0 * dram if is_number(dram) else None

    title = (f"{name} {res[0]}×{res[1]}, LVB {'on' if lvb_on else 'off'}: {cycles:,.0f} cycles"
             + (f" = {cycles / (ghz * 1e6):.4g} ms at {ghz:g} GHz" if ghz > 0 else ""))
    return dict(title=title, width=res[0], height=res[1], lvb_on=lvb_on, rays=rays, leaves=leaves,
                units=units, caches=caches, dram=dram)


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
        raise InputError(f"{path}: shape {a.shape} does not match the resolution {r['width']}x{r['height']}")
    n = len(r["rays"])
    # A bit above the last light means the file uses another layout (e.g. bit 0 = hit, bit 1+i = light i).
    if n < 16 and (a >> n).any():
        raise InputError(f"{path}: bits set above light {n}; expected bit i = light i "
                         f"for the {n} lights in report.json")
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
    ph = 3.5 * h / w  # panel height in inches: 4-inch cells hold 3.5-inch-wide images next to the labels
    fig = plt.figure(figsize=(4.0 * ncols + 0.6, nrows * (ph + 0.75) + 1.5), layout="constrained")
    # The colorbars get a row of their own: colorbars attached to panels upset the grid.
    gs = fig.add_gridspec(nrows + 1, ncols, height_ratios=[ph] * nrows + [0.12])
    axes = [fig.add_subplot(gs[k // ncols, k % ncols]) for k in range(n + 1)]
    half = (ncols + 1) // 2
    cax_lights, cax_total = fig.add_subplot(gs[nrows, :half]), fig.add_subplot(gs[nrows, half:])
    extent = (0, w, h, 0)  # axes in full-resolution pixels, row 0 at the top
    for i, (img, count) in enumerate(panels):
        im = axes[i].imshow(img, cmap="inferno", vmin=0, vmax=1, extent=extent, interpolation="antialiased")
        axes[i].set_title(f"light {i + 1}: {count:,} culled ({100.0 * count / a.size:.1f} %)", fontsize=10)
    s = axes[n].imshow(block_mean(total, f), cmap="viridis", vmin=0, vmax=n, extent=extent,
                       interpolation="antialiased")
    axes[n].set_title(f"all lights: {int(total.sum(dtype=np.int64)):,} culled", fontsize=10)
    block = "pixel" if f == 1 else f"{f}×{f}-pixel block"
    fig.colorbar(im, cax=cax_lights, orientation="horizontal",
                 label=f"light panels: fraction of shadow rays culled per {block}")
    fig.colorbar(s, cax=cax_total, orientation="horizontal",
                 label="all lights: culled lights per pixel" + ("" if f == 1 else " (block mean)"))
    for ax in axes:
        ax.set_xlabel("x (px)")
        ax.set_ylabel("y (px)")
    fig.suptitle(f"{r['title']}\nshadow rays from primary hits culled by the LVB (% of all {w}×{h} pixels)")
    save(fig, path, written)


def plot_culling(r, path, written):
    if not r["lvb_on"]:
        fig, ax = plt.subplots(figsize=(8, 3), layout="constrained")
        ax.set_axis_off()
        ax.text(0.5, 0.5, "LVB culling was off in this run:\nno leaves or shadow rays were culled.",
                ha="center", va="center", fontsize=13)
        fig.suptitle(r["title"])
        save(fig, path, written)
        return
    n = max(len(r["rays"]), len(r["leaves"] or []))
    leaves = [pct(*r["leaves"][i]) if r["leaves"] and i < len(r["leaves"]) else None for i in range(n)]
    rays = [pct(r["rays"][i][1], r["rays"][i][0]) if i < len(r["rays"]) else None for i in range(n)]
    x, bw = np.arange(n), 0.38
    fig, ax = plt.subplots(figsize=(max(7.5, 0.9 * n + 3.0), 4.8), layout="constrained")
    ax.bar(x - bw / 2, [v or 0 for v in leaves], bw, label="leaves culled (% of non-empty leaves)", color="tab:blue")
    ax.bar(x + bw / 2, [v or 0 for v in rays], bw, label="shadow rays culled (% of shadow rays)", color="tab:red")
    bar_labels(ax, x - bw / 2, leaves)
    bar_labels(ax, x + bw / 2, rays)
    ax.set_xticks(x, [f"L{i + 1}" for i in range(n)])
    ax.set_xlabel("light")
    ax.set_ylabel("culled (%)")
    top = max([100.0] + [v for v in leaves + rays if v is not None])  # over 100 % is wrong, but show it
    ax.set_ylim(0, 1.25 * top)  # headroom for the value labels and the legend
    ax.set_yticks(range(0, int(top) + 1, 20))
    ax.legend(loc="upper center", ncol=2, fontsize=9, frameon=False)
    ax.grid(axis="y", alpha=0.3)
    shadow, culled = sum(s for s, _ in r["rays"]), sum(c for _, c in r["rays"])
    overall = pct(culled, shadow)
    ax.set_title(f"{r['title']}\nLVB culling per light"
                 + (f" (all lights: {overall:.1f} % of {shadow:,.0f} shadow rays culled)"
                    if overall is not None else ""),
                 fontsize=10)
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
                ax.text(left + share / 2, yi, f"{share:.0f} %", ha="center", va="center", fontsize=8)
            left += share
    ax.set_yticks(y, [u[0] for u in units])
    ax.invert_yaxis()  # pipeline order from the top
    ax.set_xlim(0, 100)
    ax.set_xlabel("share of unit cycles (%), summed over the units of a type")
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=3, fontsize=9, frameon=False)
    fig.suptitle(f"{r['title']}\nunit time breakdown", fontsize=10)
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


def run(folder, written):
    r = load_parsed(folder, "report.json", parse_report)
    npy = os.path.join(folder, "culled.npy")
    culled = load_culled(npy, r) if os.path.exists(npy) else None
    if culled is not None:
        plot_culled(culled, r, os.path.join(folder, "culled.png"), written)
    plot_culling(r, os.path.join(folder, "plot_culling.png"), written)
    plot_time_breakdown(r, os.path.join(folder, "plot_time_breakdown.png"), written)
    plot_cache_hit_rates(r, os.path.join(folder, "plot_cache_hit_rates.png"), written)


# --------------------------------------------------------------------------------------------- sweep


def fmt_value(v):
    if isinstance(v, float):
        return f"{v:g}"
    return str(v)  # bools print as True/False, like the labels in the sweep runner


def unit_of(name):
    """A best guess at the unit from a metric or axis name, for the axis labels."""
    n = name.lower()
    if re.search(r"(^|[._])ms($|[._])", n):
        return "ms"
    if n.endswith("rate"):
        return "0–1"
    if "cycles" in n:
        return "cycles"
    for suffix, unit in (("_kb", "KB"), ("_mb", "MB"), ("_bytes", "bytes"), ("_ghz", "GHz"), ("_seconds", "s")):
        if n.endswith(suffix):
            return unit
    return None


def labelled(name):
    unit = unit_of(name)
    return f"{name} ({unit})" if unit else name


def sanitize(name):
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name)


def check_schema(doc, where, schema):
    if not isinstance(doc, dict):
        raise InputError(f"{where}: not a JSON object")
    if doc.get("schema") != schema:
        raise InputError(f"{where}: schema is {doc.get('schema')!r}, expected {schema!r}")


def parse_results(res):
    where = "results.json"
    check_schema(res, where, "rtsim-sweep/1")
    axes, metrics, rows = (field(res, key, where=where) for key in ("axes", "metrics", "rows"))
    for key, v in (("axes", axes), ("metrics", metrics)):
        if not isinstance(v, list) or not all(isinstance(s, str) for s in v):
            raise InputError(f"{where}: field '{key}' is not a list of names")
    if not isinstance(rows, list) or not all(isinstance(r, dict) for r in rows):
        raise InputError(f"{where}: field 'rows' is not a list of objects")
    for i, row in enumerate(rows):
        for a in axes:
            if a not in row:
                raise InputError(f"{where}: rows[{i}] has no value for axis '{a}'")
        for m in metrics:
            v = row.get(m)
            if v is not None and not is_number(v):
                raise InputError(f"{where}: rows[{i}]: metric '{m}' is not a number or null")
    if all(isinstance(r.get("point"), int) for r in rows):
        rows = sorted(rows, key=lambda r: r["point"])  # the order of points, whatever order they finished in
    return str(res.get("name", "")), axes, metrics, rows


def distinct(rows, axis):
    """The values of axis in first-seen order; JSON text as the key so True and 1 stay apart."""
    seen = {}
    for row in rows:
        seen.setdefault(json.dumps(row.get(axis), sort_keys=True), row.get(axis))
    return list(seen.values())


def plot_metric(rows, metric, axis, values, others, title_extra, path, written):
    numeric = all(is_number(v) for v in values)
    pow2 = numeric and all(v > 0 and math.log2(v) == round(math.log2(v)) for v in values)
    keys = [json.dumps(v, sort_keys=True) for v in values]

    # One series per combination of the other varying axes, in first-seen order.
    series = {}
    for row in rows:
        combo = tuple(json.dumps(row.get(b), sort_keys=True) for b in others)
        label = ", ".join(f"{b}={fmt_value(row.get(b))}" for b in others)
        series.setdefault(combo, (label, {}))
        v = row.get(metric)
        if v is not None:
            x = float(row[axis]) if numeric else keys.index(json.dumps(row[axis], sort_keys=True))
            series[combo][1].setdefault(x, []).append(v)
    shown = list(series.values())[:MAX_SERIES]

    fig, ax = plt.subplots(figsize=(9, 5), layout="constrained")
    plotted = 0
    for label, points in shown:
        xs = sorted(points)
        if xs:
            # Repeated points (same x and combination) are averaged.
            ax.plot(xs, [sum(points[x]) / len(points[x]) for x in xs], marker="o", label=label or metric)
            plotted += 1
    if not plotted:
        ax.text(0.5, 0.5, "no values yet", transform=ax.transAxes, ha="center", va="center", color="dimgray")
    if pow2:
        ax.set_xscale("log", base=2)
        ax.xaxis.set_minor_locator(NullLocator())
    if numeric:
        if len(values) <= 12:
            ax.set_xticks(values, [fmt_value(v) for v in values])
    else:
        labels = [fmt_value(v) for v in values]
        ax.set_xticks(range(len(values)), labels, rotation=30 if sum(map(len, labels)) > 60 else 0)
        ax.set_xlim(-0.5, len(values) - 0.5)
    ax.set_xlabel(labelled(axis) + (" (log₂ scale)" if pow2 else ""))
    ax.set_ylabel(labelled(metric))
    ax.grid(alpha=0.3)
    if plotted and others:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, title="series")
    title = f"{metric} vs {axis}\n{title_extra}"
    if len(series) > MAX_SERIES:
        title += f" — first {MAX_SERIES} of {len(series)} series shown"
    ax.set_title(title, fontsize=10)
    save(fig, path, written)


def sweep(folder, written):
    name, axes, metrics, rows = load_parsed(folder, "results.json", parse_results)
    scenes = distinct(rows, "scene")
    if len(scenes) > 1 and "scene" not in axes:
        axes = axes + ["scene"]  # several scenes: the scene is one more axis
    varying = [a for a in axes if len(distinct(rows, a)) >= 2]
    title_extra = f"sweep {name}" + (f", scene {scenes[0]}" if len(scenes) == 1 and scenes[0] is not None else "")
    title_extra += f", {len(rows)} points"

    out = os.path.join(folder, "plots")
    os.makedirs(out, exist_ok=True)
    files = []
    for metric in metrics:
        for axis in varying:
            fname = f"{sanitize(metric)}_vs_{sanitize(axis)}.png"
            if fname in files:
                raise InputError(f"results.json: two metric/axis pairs give the file name {fname}")
            files.append(fname)
            others = [b for b in varying if b != axis]
            plot_metric(rows, metric, axis, distinct(rows, axis), others, title_extra,
                        os.path.join(out, fname), written)
    lines = [f"# Sweep {name}: plots", ""] + [f"- [{f}]({f})" for f in files]
    if not files:
        lines.append("No axis has two or more values yet: nothing to plot.")
    write_text(os.path.join(out, "index.md"), "\n".join(lines) + "\n", written)


# ----------------------------------------------------------------------------------------- reproduce

# One colour per source, the same in both figures; the paper's figures are the reference, in gray.
SOURCES = [("paper", "paper (published)", "tab:gray"),
           ("ours_paper", "ours, paper's method", "tab:orange"),
           ("ours_exact", "ours, exact mode", "tab:blue")]
REPRO_COLS = 3  # scenes per row; more scenes wrap
REPRO_MIN_WIDTH = 9.5  # inches: the figure titles must fit above a single scene


def numbers(obj, key, where):
    v = field(obj, key, where=where)
    if not isinstance(v, list) or not all(is_number(x) for x in v):
        raise InputError(f"{where}: field '{key}' is not a list of numbers")
    return [float(x) for x in v]


def ratios(parts, wholes):
    return [pct(p, w) for p, w in zip(parts, wholes)]


def reduction_pct(on, off):
    return 100.0 * (off - on) / off if off > 0 else None


def parse_reproduction(rep):
    """Per scene, the percentages both figures need, checked up front so bad input writes no file."""
    where = "reproduction.json"
    check_schema(rep, where, "rtsim-reproduction/1")
    scenes = field(rep, "scenes", where=where)
    if not isinstance(scenes, list) or not all(isinstance(s, dict) for s in scenes):
        raise InputError(f"{where}: field 'scenes' is not a list of objects")
    out = []
    for i, sc in enumerate(scenes):
        w = f"{where}: scenes[{i}]"
        name = field(sc, "name", where=w)
        title = field(sc, "title", name, where=w)
        if not isinstance(name, str) or not isinstance(title, str):
            raise InputError(f"{w}: fields 'name' and 'title' must be strings")
        s = dict(title=title, rays={}, leaves={}, time={}, ms={}, pixels={}, missing=[])
        paper = field(sc, "paper", None, where=w)
        if paper is None:
            s["missing"].append("the paper's figures")
        else:
            wp = f"{w}.paper"
            per_light = number(paper, "shadow_rays_per_light", wp)
            s["rays"]["paper"] = [pct(c, per_light) for c in numbers(paper, "culled_rays", wp)]
            leaves = number(paper, "leaves", wp)
            s["leaves"]["paper"] = [pct(c, leaves) for c in numbers(paper, "culled_leaves", wp)]
            ms = {k: number(paper, f"ms.{k}", wp) for k in ("all_on", "all_off", "shadow_on", "shadow_off")}
            s["ms"]["paper"] = ms
            s["time"]["paper"] = [reduction_pct(ms[f"{k}_on"], ms[f"{k}_off"]) for k in ("all", "shadow")]
        ours = field(sc, "ours", {}, where=w)
        if not isinstance(ours, dict):
            raise InputError(f"{w}: field 'ours' is not an object")
        off = ours.get("off")
        if off is not None:
            off = [number(off, f"frame_ms_{k}", f"{w}.ours.off") for k in ("all", "shadow")]
        else:
            s["missing"].append("our culling-off run")
        for var, key, label in (("paper", "ours_paper", "our paper's-method run"),
                                ("exact", "ours_exact", "our exact-mode run")):
            o = ours.get(var)
            if o is None:
                s["missing"].append(label)
                continue
            wo = f"{w}.ours.{var}"
            culled, shadow = numbers(o, "culled_rays", wo), numbers(o, "shadow_rays", wo)
            cl, ne = numbers(o, "culled_leaves", wo), numbers(o, "nonempty_leaves", wo)
            if len(culled) != len(shadow) or len(cl) != len(ne):
                raise InputError(f"{wo}: per-light lists of different lengths")
            s["rays"][key], s["leaves"][key] = ratios(culled, shadow), ratios(cl, ne)
            on = [number(o, f"frame_ms_{k}", wo) for k in ("all", "shadow")]
            s["ms"][key] = on
            s["time"][key] = [reduction_pct(a, b) for a, b in zip(on, off)] if off else [None, None]
            px = o.get("pixels_shadow_differs_from_off")
            if px is not None:
                if not is_number(px):
                    raise InputError(f"{wo}: field 'pixels_shadow_differs_from_off' is not a number")
                s["pixels"][key] = px
        s["ms"]["off"] = off
        out.append(s)
    return out


def fmt_pct(v):
    # Two decimals below 1 %: the paper's bunny figures (0.01 % of rays, 0.07 % of time) must not read as 0.
    if v == 0:
        return "0"
    if abs(v) < 0.005:
        return "<0.01" if v > 0 else ">-0.01"
    return f"{v:.2f}" if abs(v) < 1 else f"{v:.1f}"


def value_labels(ax, xs, values, fmt, rotation=0, fontsize=8):
    """Value at the end of each bar, offset in points so it works on any scale; "n/a" where unknown (None)."""
    for x, v in zip(xs, values):
        if v is None:
            ax.annotate("n/a", (x, 0), xytext=(0, 2), textcoords="offset points", ha="center", va="bottom",
                        fontsize=fontsize - 1, color="dimgray", rotation=90)
        else:
            down = v < 0
            ax.annotate(fmt(v), (x, v), xytext=(0, -2 if down else 2), textcoords="offset points", ha="center",
                        va="top" if down else "bottom", fontsize=fontsize, rotation=rotation)


def legend_strip(fig):
    # A subfigure of its own: matplotlib 3.6's constrained layout leaves room for no figure legend.
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for _, _, c in SOURCES]
    fig.legend(handles, [label for _, label, _ in SOURCES], loc="center", ncol=len(SOURCES), frameon=False)


def scene_grid(fig, n):
    """n scene panels in rows of REPRO_COLS; spare cells of the last row are hidden."""
    ncols = min(REPRO_COLS, n)
    axes = fig.subplots(math.ceil(n / ncols), ncols, squeeze=False).ravel()
    for ax in axes[n:]:
        ax.set_axis_off()
    return axes[:n]


def nothing_to_plot(fig):
    ax = fig.add_subplot()
    ax.set_axis_off()
    ax.text(0.5, 0.5, "reproduction.json lists no scene: no run finished.", ha="center", va="center", fontsize=13)


def panel_title(ax, s, extra=""):
    title = s["title"]
    if s["missing"]:
        # Wrapped: a scene missing everything would otherwise run into its neighbour's title.
        title += "\n" + textwrap.fill("missing: " + "; ".join(s["missing"]), 60)
    ax.set_title(title + extra, fontsize=10)


def nothing_here(ax):
    ax.text(0.5, 0.5, "nothing to compare", transform=ax.transAxes, ha="center", va="center", color="dimgray")
    ax.set_yticks([])


def per_light_panel(ax, s, kind):
    # The scene's own light count (the larger of the paper's and ours), not the widest scene's: no rows of n/a.
    nlights = max([1] + [len(v) for k in ("rays", "leaves") for v in s[k].values()])
    x, bw = np.arange(nlights), 0.27
    top = 0.0
    for k, (key, _, colour) in enumerate(SOURCES):
        if key not in s[kind]:
            continue  # the whole source is missing: said in the panel title, not with n/a on every light
        vals = s[kind][key]
        vals = [vals[i] if i < len(vals) else None for i in range(nlights)]
        xs = x + (k - 1) * bw
        ax.bar(xs, [v or 0 for v in vals], bw, color=colour)
        value_labels(ax, xs, vals, fmt_pct, rotation=90, fontsize=7)
        top = max([top] + [v for v in vals if v is not None])
    ax.set_xticks(x, [f"L{i + 1}" for i in range(nlights)])
    ax.set_xlim(-0.6, nlights - 0.4)
    ax.set_ylim(0, 1.3 * max(top, 1.0))  # headroom for the vertical value labels
    ax.grid(axis="y", alpha=0.3)
    ax.set_xlabel("light (by index)")
    if not s[kind]:
        nothing_here(ax)
        ax.set_xticks([])  # no light to name
    extra = ""
    if kind == "rays" and s["pixels"]:
        items = ", ".join(f"{label.split(', ')[1]} {s['pixels'][key]:,.0f}"
                          for key, label, _ in SOURCES if key in s["pixels"])
        head = "shadow pixels changed by culling:"
        extra = f"\n{head}" + ("\n" if len(head) + len(items) > 60 else " ") + items  # break between, not inside
    panel_title(ax, s, extra)


def plot_reproduce_culling(scenes, path, written):
    n = len(scenes)
    nlights = max([1] + [len(v) for s in scenes for kind in ("rays", "leaves") for v in s[kind].values()])
    ncols, nrows = min(REPRO_COLS, max(n, 1)), math.ceil(max(n, 1) / REPRO_COLS)
    width = max(4.8, 0.7 * nlights + 1.4)
    fig = plt.figure(figsize=(max(REPRO_MIN_WIDTH, width * ncols + 0.4), 2 * nrows * 3.9 + 1.3),
                     layout="constrained")
    fig.suptitle("LVB culling per light: the paper vs ours\n"
                 "lights go by index: the paper did not publish its light positions, ours are the scene files' own")
    if not n:
        nothing_to_plot(fig)
        save(fig, path, written)
        return
    top, rays_fig, leaves_fig = fig.subfigures(3, 1, height_ratios=[0.35, 3.9 * nrows, 3.9 * nrows])
    legend_strip(top)
    rays_fig.suptitle("shadow rays culled (% of the shadow rays to that light)", fontsize=11, fontweight="bold")
    leaves_fig.suptitle("leaves culled — the denominators differ: paper: % of all leaves; "
                        "ours: % of non-empty leaves", fontsize=11, fontweight="bold")
    for sub, kind, ylabel in ((rays_fig, "rays", "shadow rays culled (%)"),
                              (leaves_fig, "leaves", "leaves culled (%)")):
        for k, (ax, s) in enumerate(zip(scene_grid(sub, n), scenes)):
            per_light_panel(ax, s, kind)
            if k % ncols == 0:
                ax.set_ylabel(ylabel)
    save(fig, path, written)


def ms_caption(s):
    """Absolute frame times under a time panel: context only, since the models differ."""
    lines = []
    p = s["ms"].get("paper")
    if p:
        # Two decimals as published; ours with three, as in reproduction.md.
        lines.append(f"paper: all {p['all_off']:.2f} → {p['all_on']:.2f}, shadow {p['shadow_off']:.2f} → "
                     f"{p['shadow_on']:.2f} ms")
    off = s["ms"]["off"]
    for key, label, _ in SOURCES[1:]:
        on = s["ms"].get(key)
        if on:
            pairs = [f"{off[i]:.3f} → {on[i]:.3f}" if off else f"? → {on[i]:.3f}" for i in range(2)]
            lines.append(f"{label}: all {pairs[0]}, shadow {pairs[1]} ms")
    return "frame time, culling off → on:\n" + "\n".join(lines) if lines else "no frame times"


def plot_reproduce_time(scenes, path, written):
    n = len(scenes)
    ncols, nrows = min(REPRO_COLS, max(n, 1)), math.ceil(max(n, 1) / REPRO_COLS)
    fig = plt.figure(figsize=(max(REPRO_MIN_WIDTH, 5.2 * ncols + 0.4), nrows * 5.4 + 1.5), layout="constrained")
    fig.suptitle("Frame-time reduction with LVB culling, (off − on) / off\n"
                 "absolute times differ (the paper's simulator and ours model the hardware differently),\n"
                 "so the reductions are compared")
    if not n:
        nothing_to_plot(fig)
        save(fig, path, written)
        return
    top, main = fig.subfigures(2, 1, height_ratios=[0.35, 5.4 * nrows])  # legend strip, panels
    legend_strip(top)
    x, bw = np.arange(2), 0.27
    for k, (ax, s) in enumerate(zip(scene_grid(main, n), scenes)):
        vals_all = []
        for j, (key, _, colour) in enumerate(SOURCES):
            vals = s["time"].get(key, [None, None])
            xs = x + (j - 1) * bw
            ax.bar(xs, [v or 0 for v in vals], bw, color=colour)
            value_labels(ax, xs, vals, lambda v: fmt_pct(v) + " %")
            vals_all += [v for v in vals if v is not None]
        lo, hi = min([0.0] + vals_all), max([0.0] + vals_all)
        span = max(hi - lo, 1.0)
        ax.set_ylim(lo - 0.15 * span if lo < 0 else 0, hi + 0.2 * span)  # room for the value labels
        ax.axhline(0, color="black", lw=0.6)
        ax.set_xticks(x, ["all rays", "shadow rays"])
        ax.set_xlim(-0.6, 1.6)
        ax.grid(axis="y", alpha=0.3)
        ax.set_xlabel(ms_caption(s), fontsize=8, loc="left")
        if not vals_all:
            nothing_here(ax)
        if k % ncols == 0:
            ax.set_ylabel("frame-time reduction (%)")
        panel_title(ax, s)
    save(fig, path, written)


def reproduce(folder, written):
    scenes = load_parsed(folder, "reproduction.json", parse_reproduction)
    plot_reproduce_culling(scenes, os.path.join(folder, "reproduce_culling.png"), written)
    plot_reproduce_time(scenes, os.path.join(folder, "reproduce_time.png"), written)


# ---------------------------------------------------------------------------------------------- main


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line and exit status 2, like every other input error
        raise InputError(message)


# ----------------------------------------------------------------------------------------- animate

def read_csv(folder, name):
    """Rows of folder/name as dicts of floats (None for an empty cell)."""
    path = os.path.join(folder, name)
    try:
        with open(path, encoding="utf-8", newline="") as f:
            rows = list(csv.DictReader(f))
    except FileNotFoundError:
        raise InputError(f"{path}: not found") from None
    out = []
    for i, row in enumerate(rows, start=2):
        parsed = {}
        for k, v in row.items():
            try:
                parsed[k] = float(v) if v not in ("", None) else None
            except ValueError:
                raise InputError(f"{path}:{i}: column '{k}' is not a number: {v!r}") from None
        if parsed.get("time") is None:
            raise InputError(f"{path}:{i}: missing time")
        out.append(parsed)
    return out


def series(rows, key):
    return [r.get(key) if r.get(key) is not None else math.nan for r in rows]


def time_axis(ax, title):
    ax.set_xlabel("scene time (s)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)


def write_gif(folder, times, written):
    from PIL import Image  # Debian's python3-pil, which matplotlib depends on

    frames_dir = os.path.join(folder, "frames")
    names = sorted(n for n in os.listdir(frames_dir) if re.fullmatch(r"frame_\d{4}\.png", n)) \
        if os.path.isdir(frames_dir) else []
    if not names:
        return
    images = [Image.open(os.path.join(frames_dir, n)).convert("RGB") for n in names]
    # One frame per sample at the scene's pace (its time step in seconds), at least 50 ms.
    step = (times[-1] - times[0]) / (len(times) - 1) if len(times) > 1 else 0.1
    duration = max(50, int(round(step * 1000)))
    write_atomically(os.path.join(folder, "frames.gif"),
                     lambda tmp: images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:],
                                                duration=duration, loop=0),
                     written)


def animate(folder, written):
    rows = read_csv(folder, "frames.csv")
    host = {r["time"]: r for r in read_csv(folder, "host.csv")}
    if not rows:
        raise InputError(os.path.join(folder, "frames.csv") + ": no frames")
    t = [r["time"] for r in rows]
    out = os.path.join(folder, "plots")
    os.makedirs(out, exist_ok=True)

    fig, ax = plt.subplots(figsize=(7, 4))
    for key, label, colour in (("cycles_off", "culling off", "tab:gray"), ("cycles_on", "culling on", "tab:blue")):
        ax.plot(t, series(rows, key), marker="o", ms=3, label=label, color=colour)
    ax.set_ylabel("cycles per frame")
    ax.set_ylim(bottom=0)
    ax.legend()
    time_axis(ax, "Simulated cycles per frame")
    save(fig, os.path.join(out, "animate_cycles.png"), written)

    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(t, [100 * v for v in series(rows, "culled_share")], marker="o", ms=3, label="shadow rays culled")
    lights = sorted(k for k in rows[0] if re.fullmatch(r"culled_leaves_l\d+", k))
    leaf_share = []
    for r in rows:
        culled = [r[k] for k in lights if r.get(k) is not None]
        bits = (r.get("nonempty_leaves") or 0) * len(culled)
        leaf_share.append(100 * sum(culled) / bits if bits else math.nan)
    ax.plot(t, leaf_share, marker="s", ms=3, label="(leaf, light) bits 0")
    ax.set_ylabel("%")
    ax.set_ylim(0, 100)
    ax.legend()
    time_axis(ax, "What the LVB culls, per frame")
    save(fig, os.path.join(out, "animate_culled.png"), written)

    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4))
    for key, label in (("kdtree_seconds", "kd-tree build"), ("lvb_seconds", "LVB (hierarchical)")):
        a.plot(t, [host.get(x, {}).get(key) or math.nan for x in t], marker="o", ms=3, label=label)
    a.set_ylabel("host seconds")
    a.set_ylim(bottom=0)
    a.legend()
    time_axis(a, "Rebuild time on the host, per frame")
    for key, label in (("lvb_nodes_visited", "kd-tree nodes visited"), ("lvb_region_tests", "region (box) tests"),
                       ("lvb_pair_tests", "triangle-pair tests")):
        b.plot(t, series(rows, key), marker="o", ms=3, label=label)
    b.set_yscale("log")
    b.set_ylabel("count per frame")
    b.legend()
    time_axis(b, "LVB work per frame")
    fig.tight_layout()
    save(fig, os.path.join(out, "animate_preprocessing.png"), written)

    write_gif(folder, t, written)
    write_text(os.path.join(folder, "summary.md"), animate_summary(rows, host), written)


def median(values):
    v = sorted(x for x in values if x is not None and not math.isnan(x))
    if not v:
        return math.nan
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def animate_summary(rows, host):
    """Markdown: a row per frame, then the medians. Builder cycles assume one test (region or pair) per cycle."""
    def cell(v, fmt="{:,.0f}"):
        return "" if v is None or (isinstance(v, float) and math.isnan(v)) else fmt.format(v)

    def ratio(a, b):
        return a / b if a is not None and b else None

    table = []
    for r in rows:
        h = host.get(r["time"], {})
        saved = (r["cycles_off"] - r["cycles_on"]) if r.get("cycles_off") is not None and r.get("cycles_on") is not None else None
        build = (r["lvb_region_tests"] + r["lvb_pair_tests"]) if r.get("lvb_region_tests") is not None else None
        lazy = (r["lazy_region_tests"] + r["lazy_pair_tests"] + r["lazy_dirty_tests"]) \
            if r.get("lazy_region_tests") is not None else None
        table.append({"time": r["time"], "saved": saved, "share": r.get("culled_share"), "build": build,
                      "pays": ratio(saved, build), "lvb_s": h.get("lvb_seconds"), "kd_s": h.get("kdtree_seconds"),
                      "dirty": ratio(r.get("lazy_dirty_pairs"), r.get("lazy_pairs")), "lazy": lazy,
                      "lazy_share": ratio(lazy, build), "lazy_pays": ratio(saved, lazy),
                      "off": r.get("cycles_off"), "on": r.get("cycles_on")})
    head = ("| time | cycles off | cycles on | saved cycles | shadow rays culled | LVB tests (builder cycles) "
            "| saved / LVB tests | LVB s | kd-tree s | lazy: dirty pairs | lazy: tests | lazy / full "
            "| saved / lazy tests |")
    lines = ["# Culling against its recomputation, per frame", "",
             "Builder cycles: the LVB's region and pair tests at one test per cycle; lazy tests add the "
             "dirty tests that find the pairs to redo. Host seconds vary from run to run (host.csv).", "",
             head, "|" + "---|" * 13]
    pct = "{:.1%}"
    for x in table:
        lines.append("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |".format(
            f"{x['time']:g}", cell(x["off"]), cell(x["on"]), cell(x["saved"]), cell(x["share"], pct),
            cell(x["build"]), cell(x["pays"], "{:.4f}"), cell(x["lvb_s"], "{:.2f}"), cell(x["kd_s"], "{:.2f}"),
            cell(x["dirty"], pct), cell(x["lazy"]), cell(x["lazy_share"], pct), cell(x["lazy_pays"], "{:.4f}")))
    m = {k: median([x[k] for x in table]) for k in table[0] if k != "time"}
    lines.append("| **median** | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |".format(
        cell(m["off"]), cell(m["on"]), cell(m["saved"]), cell(m["share"], pct), cell(m["build"]),
        cell(m["pays"], "{:.4f}"), cell(m["lvb_s"], "{:.2f}"), cell(m["kd_s"], "{:.2f}"), cell(m["dirty"], pct),
        cell(m["lazy"]), cell(m["lazy_share"], pct), cell(m["lazy_pays"], "{:.4f}")))
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------------------------- area

SAMPLES = "scene.lights.area_from_points.samples"


def area_bounds(folder, pairs):
    """What bounds the shadow phase, from the points' report.json: culling can only save the work of
    the rays it removes, and that work shows in the frame only where nothing else hides it."""
    def stats(row):
        path = os.path.join(folder, "points", str(row.get("id", "")), "report.json")
        return load_json(path) if os.path.exists(path) else None

    def total(r, unit, kind):
        return r["stats"][unit]["total"][kind]

    out = []
    for scene, n, off_row, on_row in pairs:
        off, on = stats(off_row), stats(on_row)
        if not off or not on:
            continue
        trv = {k: total(off, "trv", k) for k in ("busy_cycles", "stalled_cycles", "idle_cycles")}
        removed = {u: 1 - total(on, u, "busy_cycles") / total(off, u, "busy_cycles") for u in ("trv", "ist")}
        shadow = 1 - on["cycles_shadow"] / off["cycles_shadow"]
        out.append(f"| {scene} | {n} | {shadow:.2%} | {removed['trv']:.2%} | {removed['ist']:.2%} | "
                   f"{trv['idle_cycles'] / sum(trv.values()):.2%} | {off['stats']['ist']['l1']['hit_rate']:.2%} |")
    if not out:
        return []
    return ["", "## What bounds the shadow phase", "",
            "From the points' report.json. Culled rays save only their own work: the TRV and IST operations "
            "culling removes (busy cycles, on against off). That work shortens the shadow phase unless something "
            "else hides it, such as the IST units' memory: TRV idle share and IST L1 hit rate with culling off.", "",
            "| scene | samples | shadow phase shorter by | TRV operations removed | IST operations removed "
            "| TRV idle (off) | IST L1 hit rate (off) |",
            "|---|---|---|---|---|---|---|"] + out


def area(folder, written):
    name, axes, metrics, rows = load_parsed(folder, "results.json", parse_results)
    for need in (SAMPLES, "run.lvb"):
        if need not in axes:
            raise InputError(f"results.json: sweep {name} has no axis {need}")
    runs = {}
    for r in rows:
        lvb = r["run.lvb"]
        on = lvb if isinstance(lvb, bool) else lvb == "on"
        runs.setdefault((r["scene"], r[SAMPLES]), {})["on" if on else "off"] = r
    lines = ["# Culling with area lights: culling off against on", "",
             f"Sweep {name}; reduction = (cycles off - cycles on) / cycles off; rays with culling on.", "",
             "| scene | samples | cycles off | cycles on | reduction | shadow rays traced | culled | culled share |",
             "|---|---|---|---|---|---|---|---|"]
    # The (scene, samples) cells that ran both ways, in order.
    pairs = [(scene, n, pair["off"], pair["on"])
             for (scene, n), pair in sorted(runs.items(), key=lambda kv: (str(kv[0][0]), kv[0][1]))
             if pair.get("off") and pair.get("on")]
    curves = {}
    for scene, n, off, on in pairs:
        red = (off["cycles_total"] - on["cycles_total"]) / off["cycles_total"]
        curves.setdefault(scene, []).append((n, red))
        lines.append(f"| {scene} | {n} | {off['cycles_total']:,} | {on['cycles_total']:,} | {red:.2%} | "
                     f"{on['rays_shadow']:,} | {on['shadow_culled']:,} | {on['shadow_culled_rate']:.2%} |")
    lines += area_bounds(folder, pairs)
    write_text(os.path.join(folder, "area_lights.md"), "\n".join(lines) + "\n", written)
    out = os.path.join(folder, "plots")
    os.makedirs(out, exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 4))
    for scene, pts in sorted(curves.items()):
        pts.sort()
        ax.plot([p[0] for p in pts], [100 * p[1] for p in pts], marker="o", label=scene)
    ax.set_xscale("log", base=2)
    ax.set_xlabel("shadow rays per hit and light (samples)")
    ax.set_ylabel("frame-time reduction with culling (%)")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(f"Culling and area lights (sweep {name})", fontsize=10)
    fig.tight_layout()
    save(fig, os.path.join(out, "area_reduction.png"), written)


def main(argv=None):
    parser = _Parser(prog="plots.py", description="PNG figures for an rtsim run, sweep or reproduce directory.")
    parser.add_argument("--verbose", action="store_true", help="list the files written")
    sub = parser.add_subparsers(dest="mode", required=True, metavar="{run,sweep,reproduce,animate,area}")
    for mode, text in (("run", "figures for a run directory (report.json, culled.npy)"),
                       ("sweep", "figures for a sweep directory (results.json)"),
                       ("reproduce", "paper-vs-ours figures for an rtsim reproduce directory (reproduction.json)"),
                       ("animate", "figures over time and frames.gif for an rtsim animate directory (frames.csv)"),
                       ("area", "culling against samples per light for an area-light sweep (results.json)")):
        p = sub.add_parser(mode, help=text)
        p.add_argument("dir", metavar="DIR")
        p.add_argument("--verbose", action="store_true", default=argparse.SUPPRESS, help="list the files written")
    written = []
    try:
        args = parser.parse_args(argv)
        if not os.path.isdir(args.dir):
            raise InputError(f"{args.dir}: not a directory")
        {"run": run, "sweep": sweep, "reproduce": reproduce, "animate": animate, "area": area}[args.mode](args.dir, written)
    except (InputError, OSError) as e:
        print("plots.py: error: " + " ".join(str(e).split()), file=sys.stderr)
        return 2
    if args.verbose:
        print("\n".join(written))
    return 0


if __name__ == "__main__":
    sys.exit(main())
