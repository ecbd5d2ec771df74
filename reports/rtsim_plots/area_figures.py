"""Culling against the samples per area light: plots/area_reduction.png (plots.py area). The sweep
writes the tables, area_lights.md, itself (reports/area_report.cpp)."""

import math
import os

from rtsim_plots.common import InputError, load_parsed, plt, save
from rtsim_plots.files import RESULTS_JSON
from rtsim_plots.sweep_figures import SAMPLED_NOTE, parse_results


SAMPLES = "scene.lights.area_from_points.samples"


def reduction_ci(off, on):
    """The 95% half-interval of 1 - on / off from sampled rows' intervals (cycles_total_ci95), their
    relative errors added in quadrature as if the two estimates were independent (the pair shares
    the plan, so this errs wide); 0 for full runs."""
    a, b = (r.get("cycles_total_ci95") if r.get("sampled") is True else 0 for r in (on, off))
    if not (a or b):
        return 0.0
    c_on, c_off = on["cycles_total"], off["cycles_total"]
    return c_on / c_off * math.hypot((a or 0) / c_on, (b or 0) / c_off)


def area(folder, written):
    name, axes, metrics, rows = load_parsed(folder, RESULTS_JSON, parse_results)
    for need in (SAMPLES, "run.lvb"):
        if need not in axes:
            raise InputError(f"{RESULTS_JSON}: sweep {name} has no axis {need}")
    runs = {}
    for r in rows:
        lvb = r["run.lvb"]
        on = lvb if isinstance(lvb, bool) else lvb == "on"
        runs.setdefault((r["scene"], r[SAMPLES]), {})["on" if on else "off"] = r
    # The (scene, samples) cells that ran both ways, in order.
    pairs = [
        (scene, n, pair["off"], pair["on"])
        for (scene, n), pair in sorted(runs.items(), key=lambda kv: (str(kv[0][0]), kv[0][1]))
        if pair.get("off") and pair.get("on")
    ]
    curves = {}
    for scene, n, off, on in pairs:
        red = (off["cycles_total"] - on["cycles_total"]) / off["cycles_total"]
        curves.setdefault(scene, []).append((n, red, reduction_ci(off, on)))
    # Sampled points: each reduction with its 95% interval.
    sampled = any(p[2] for pts in curves.values() for p in pts)
    out = os.path.join(folder, "plots")
    os.makedirs(out, exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 4))
    for scene, pts in sorted(curves.items()):
        pts.sort(key=lambda p: p[:2])
        xs, ys = [p[0] for p in pts], [100 * p[1] for p in pts]
        if sampled:
            ax.errorbar(xs, ys, yerr=[100 * p[2] for p in pts], marker="o", capsize=3, label=scene)
        else:
            ax.plot(xs, ys, marker="o", label=scene)
    ax.set_xscale("log", base=2)
    ax.set_xlabel("shadow rays per hit and light (samples)")
    ax.set_ylabel("frame-time reduction with culling (%)")
    if min(100 * (p[1] - p[2]) for pts in curves.values() for p in pts) >= 0:
        ax.set_ylim(bottom=0)
    else:  # culling made a frame slower: keep that point in view, and where zero is
        ax.axhline(0, color="0.4", lw=0.8)
    ax.grid(alpha=0.3)
    ax.legend()
    note = f"\nerror bars: {SAMPLED_NOTE}, as if off and on were independent" if sampled else ""
    ax.set_title(f"Culling and area lights (sweep {name}){note}", fontsize=10)
    fig.tight_layout()
    save(fig, os.path.join(out, "area_reduction.png"), written)
