"""Culling against the samples per area light: area_lights.md and plots/area_reduction.png
(plots.py area)."""

import os

from rtsim_plots.common import InputError, load_json, load_parsed, plt, save, write_text
from rtsim_plots.files import POINTS_DIR, REPORT_JSON, RESULTS_JSON
from rtsim_plots.sweep_figures import parse_results


SAMPLES = "scene.lights.area_from_points.samples"


def area_bounds(folder, pairs):
    """What bounds the shadow phase, from the points' report.json: culling can only save the work of
    the rays it removes, and that work shows in the frame only where nothing else hides it."""

    def stats(row):
        path = os.path.join(folder, POINTS_DIR, str(row.get("id", "")), REPORT_JSON)
        return load_json(path) if os.path.exists(path) else None

    def total(r, unit, kind):
        return r["stats"][unit]["total"][kind]

    out = []
    for scene, n, off_row, on_row in pairs:
        off, on = stats(off_row), stats(on_row)
        if not off or not on:
            continue
        trv = {k: total(off, "trv", k) for k in ("busy_cycles", "stalled_cycles", "idle_cycles")}
        removed = {
            u: 1 - total(on, u, "busy_cycles") / total(off, u, "busy_cycles")
            for u in ("trv", "ist")
        }
        shadow = 1 - on["cycles_shadow"] / off["cycles_shadow"]
        out.append(
            f"| {scene} | {n} | {shadow:.2%} | {removed['trv']:.2%} | {removed['ist']:.2%} | "
            f"{trv['idle_cycles'] / sum(trv.values()):.2%} | "
            f"{off['stats']['ist']['l1']['hit_rate']:.2%} |"
        )
    if not out:
        return []
    return [
        "",
        "## What bounds the shadow phase",
        "",
        "From the points' report.json. Culled rays save only their own work: the TRV and IST "
        "operations culling removes (busy cycles, on against off). That work shortens the shadow "
        "phase unless something else hides it, such as the IST units' memory: TRV idle share and "
        "IST L1 hit rate with culling off.",
        "",
        "| scene | samples | shadow phase shorter by | TRV operations removed "
        "| IST operations removed | TRV idle (off) | IST L1 hit rate (off) |",
        "|---|---|---|---|---|---|---|",
    ] + out


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
    lines = [
        "# Culling with area lights: culling off against on",
        "",
        f"Sweep {name}; reduction = (cycles off - cycles on) / cycles off; rays with culling on.",
        "",
        "| scene | samples | cycles off | cycles on | reduction | shadow rays traced | culled "
        "| culled share |",
        "|---|---|---|---|---|---|---|---|",
    ]
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
        lines.append(
            f"| {scene} | {n} | {off['cycles_total']:,} | {on['cycles_total']:,} | {red:.2%} | "
            f"{on['rays_shadow']:,} | {on['shadow_culled']:,} | {on['shadow_culled_rate']:.2%} |"
        )
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
    if min(100 * p[1] for pts in curves.values() for p in pts) >= 0:
        ax.set_ylim(bottom=0)
    else:  # culling made a frame slower: keep that point in view, and where zero is
        ax.axhline(0, color="0.4", lw=0.8)
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(f"Culling and area lights (sweep {name})", fontsize=10)
    fig.tight_layout()
    save(fig, os.path.join(out, "area_reduction.png"), written)
