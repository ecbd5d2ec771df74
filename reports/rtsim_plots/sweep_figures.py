"""Figures of a sweep: plots/<metric>_vs_<axis>.png (plots.py sweep), and with the metrics
energy_uj and frame_ms_all, plots/energy_and_time_vs_<axis>.png (each series' energy-optimal and
time-optimal values marked). The sweep lists them in plots/index.md itself (reports/sweep_index.h,
by the same names)."""

import json
import math
import os
import re

from matplotlib.ticker import NullLocator

from rtsim_plots.common import (
    InputError,
    MAX_SERIES,
    field,
    is_number,
    load_parsed,
    plt,
    save,
)
from rtsim_plots.files import RESULTS_JSON


# A sampled point's row carries each estimate's 95% half-interval
# (testbench/studies/sweep_metrics.h):
# the metric's column of intervals.
INTERVALS = {
    "cycles_total": "cycles_total_ci95",
    "cycles_primary": "cycles_primary_ci95",
    "cycles_shadow": "cycles_shadow_ci95",
    "frame_ms_all": "frame_ms_all_ci95",
    "frame_ms_shadow": "frame_ms_shadow_ci95",
    "frame_ms.all": "frame_ms_all_ci95",
    "frame_ms.shadow": "frame_ms_shadow_ci95",
}
SAMPLED_NOTE = "sampled, 95% interval"


def interval(row, metric):
    """The 95% half-interval of a sampled row's estimate of metric; 0 for a full run's (exact)
    figure; None when the metric has no interval or a sampled row lacks it."""
    key = INTERVALS.get(metric)
    if key is None:
        return None
    if row.get("sampled") is not True:
        return 0.0
    v = row.get(key)
    return float(v) if is_number(v) else None


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
    for suffix, unit in (
        ("_kb", "KB"),
        ("_mb", "MB"),
        ("_bytes", "bytes"),
        ("_ghz", "GHz"),
        ("_seconds", "s"),
    ):
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
    where = RESULTS_JSON
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
        # The order of points, whatever order they finished in.
        rows = sorted(rows, key=lambda r: r["point"])
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

    # One series per combination of the other varying axes, in first-seen order; each point its
    # values and their intervals.
    series = {}
    for row in rows:
        combo = tuple(json.dumps(row.get(b), sort_keys=True) for b in others)
        label = ", ".join(f"{b}={fmt_value(row.get(b))}" for b in others)
        series.setdefault(combo, (label, {}))
        v = row.get(metric)
        if v is not None:
            x = float(row[axis]) if numeric else keys.index(json.dumps(row[axis], sort_keys=True))
            series[combo][1].setdefault(x, []).append((v, interval(row, metric)))
    shown = list(series.values())[:MAX_SERIES]
    # Error bars when a point shown was sampled and the metric has intervals; a sampled point
    # without one (too few units drawn for an interval) gets none, and the title says so.
    sampled = INTERVALS.get(metric) is not None and any(
        row.get("sampled") is True and row.get(metric) is not None for row in rows
    )
    unknown = sampled and any(
        ci is None for _, points in shown for p in points.values() for _, ci in p
    )

    fig, ax = plt.subplots(figsize=(9, 5), layout="constrained")
    plotted = 0
    for label, points in shown:
        xs = sorted(points)
        if not xs:
            continue
        # Repeated points (same x and combination) are averaged, and so are their estimates: the
        # mean's interval is the root of the intervals' squares over their number.
        ys = [sum(v for v, _ in points[x]) / len(points[x]) for x in xs]
        if sampled:
            errs = [
                math.sqrt(sum((ci or 0) ** 2 for _, ci in points[x])) / len(points[x]) for x in xs
            ]
            ax.errorbar(xs, ys, yerr=errs, marker="o", capsize=3, label=label or metric)
        else:
            ax.plot(xs, ys, marker="o", label=label or metric)
        plotted += 1
    if not plotted:
        ax.text(
            0.5,
            0.5,
            "no values yet",
            transform=ax.transAxes,
            ha="center",
            va="center",
            color="dimgray",
        )
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
    if sampled:
        title += f"\nerror bars: {SAMPLED_NOTE}"
        title += " (unknown for some points: too few units drawn)" if unknown else ""
    if len(series) > MAX_SERIES:
        title += f" — first {MAX_SERIES} of {len(series)} series shown"
    ax.set_title(title, fontsize=10)
    save(fig, path, written)


def sweep(folder, written):
    name, axes, metrics, rows = load_parsed(folder, RESULTS_JSON, parse_results)
    scenes = distinct(rows, "scene")
    if len(scenes) > 1 and "scene" not in axes:
        axes = axes + ["scene"]  # several scenes: the scene is one more axis
    varying = [a for a in axes if len(distinct(rows, a)) >= 2]
    title_extra = f"sweep {name}" + (
        f", scene {scenes[0]}" if len(scenes) == 1 and scenes[0] is not None else ""
    )
    title_extra += f", {len(rows)} points"

    out = os.path.join(folder, "plots")
    os.makedirs(out, exist_ok=True)
    files = []
    for metric in metrics:
        for axis in varying:
            fname = f"{sanitize(metric)}_vs_{sanitize(axis)}.png"
            if fname in files:
                raise InputError(
                    f"{RESULTS_JSON}: two metric/axis pairs give the file name {fname}"
                )
            files.append(fname)
            others = [b for b in varying if b != axis]
            plot_metric(
                rows,
                metric,
                axis,
                distinct(rows, axis),
                others,
                title_extra,
                os.path.join(out, fname),
                written,
            )
    if "energy_uj" in metrics and "frame_ms_all" in metrics:
        for axis in varying:
            if axis == "scene":
                continue
            others = [b for b in varying if b != axis]
            path = os.path.join(out, f"energy_and_time_vs_{sanitize(axis)}.png")
            energy_and_time(rows, axis, distinct(rows, axis), others, title_extra, path, written)


def optimum(points):
    """The x of the smallest y (the first such x): the optimal value of an axis for a series."""
    return min(sorted(points), key=lambda x: points[x])


def energy_and_time(rows, axis, values, others, title_extra, path, written):
    """Energy per frame and frame time against one axis, a panel each, one line per series, each
    series' optimum ringed and named in the legend: the energy-optimal and the time-optimal value
    of the axis, which need not be the same."""
    numeric = all(is_number(v) for v in values)
    keys = [json.dumps(v, sort_keys=True) for v in values]
    series = {}
    for row in rows:
        combo = tuple(json.dumps(row.get(b), sort_keys=True) for b in others)
        label = ", ".join(f"{b}={fmt_value(row.get(b))}" for b in others)
        x = float(row[axis]) if numeric else keys.index(json.dumps(row[axis], sort_keys=True))
        _, energy, time = series.setdefault(combo, (label, {}, {}))
        if row.get("energy_uj") is not None and row.get("frame_ms_all") is not None:
            energy[x] = row["energy_uj"]
            time[x] = row["frame_ms_all"]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 7), layout="constrained", sharex=True)
    for label, energy, time in list(series.values())[:MAX_SERIES]:
        if not energy:
            continue
        xs = sorted(energy)
        for ax, ys, what in ((top, energy, "energy"), (bottom, time, "time")):
            best = optimum(ys)
            name = fmt_value(values[int(best)]) if not numeric else fmt_value(best)
            line = ax.plot(xs, [ys[x] for x in xs], marker="o")[0]
            ax.plot(
                [best],
                [ys[best]],
                marker="o",
                markersize=14,
                fillstyle="none",
                color=line.get_color(),
                label=f"{label or what}: {what}-optimal at {name}",
            )
    for ax, metric in ((top, "energy_uj"), (bottom, "frame_ms_all")):
        ax.set_ylabel(labelled(metric) if metric != "energy_uj" else "energy per frame (uJ)")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    pow2 = numeric and all(v > 0 and math.log2(v) == round(math.log2(v)) for v in values)
    if pow2:
        bottom.set_xscale("log", base=2)
        bottom.xaxis.set_minor_locator(NullLocator())
    if not numeric:
        bottom.set_xticks(range(len(values)), [fmt_value(v) for v in values])
    elif len(values) <= 12:
        bottom.set_xticks(values, [fmt_value(v) for v in values])
    bottom.set_xlabel(labelled(axis) + (" (log₂ scale)" if pow2 else ""))
    top.set_title(
        f"energy and time vs {axis} (ringed: each series' optimum)\n{title_extra}", fontsize=10
    )
    save(fig, path, written)
