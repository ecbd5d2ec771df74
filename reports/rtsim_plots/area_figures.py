"""Culling against the samples per area light: plots/area_reduction.png (plots.py area). The sweep
writes the tables, area_lights.md, itself (reports/area_report.cpp)."""

import os

from rtsim_plots.common import InputError, load_parsed, plt, save
from rtsim_plots.files import RESULTS_JSON
from rtsim_plots.sweep_figures import parse_results


SAMPLES = "scene.lights.area_from_points.samples"


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
        curves.setdefault(scene, []).append((n, red))
    out = os.path.join(folder, "plots")
    os.makedirs(out, exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 4))
    for scene, pts in sorted(curves.items()):
        pts.sort()
        ax.plot([p[0] for p in pts], [100 * p[1] for p in pts], marker="o", label=scene)
    ax.set_xscale("log", base=2)
    ax.set_xlabel("shadow rays per hit and light (samples)")
    ax.set_ylabel("frame-time reduction with culling (%)")
    if min(100 * p[1] for pts in curves.values() for p in pts) >= 0:
        ax.set_ylim(bottom=0)
    else:  # culling made a frame slower: keep that point in view, and where zero is
        ax.axhline(0, color="0.4", lw=0.8)
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(f"Culling and area lights (sweep {name})", fontsize=10)
    fig.tight_layout()
    save(fig, os.path.join(out, "area_reduction.png"), written)
