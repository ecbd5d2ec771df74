"""A run's energy figure, plot_energy.png (plots.py run, beside the time figures): report.json's
`energy` (docs/energy.md) by part and by ray type, under the frame's cycles."""

from rtsim_plots.common import InputError, field, is_number, number, plt, save
from rtsim_plots.files import REPORT_JSON

DYNAMIC, STATIC = "tab:blue", "lightgray"


def parse_energy(rep):
    """(parts, ray types, totals) of the report's energy section, or None when the run was not
    priced: parts are (label, dynamic uJ, static uJ) in the report's order (each unit type's
    operations, each cache, the crossbars together, the DRAM's commands, its background)."""
    e = field(rep, "energy", None)
    if e is None:
        return None
    where = f"{REPORT_JSON}: energy"

    def parts_of(name, with_static):
        entries = field(e, name, where=where)
        if not isinstance(entries, list):
            raise InputError(f"{where}: field '{name}' is not a list")
        out = []
        for i, p in enumerate(entries):
            at = f"{where}.{name}[{i}]"
            label = field(p, "label", where=at)
            if name == "caches":
                label += " " + str(field(p, "level", where=at))
            static = number(p, "static_uj", where=at) if with_static else 0.0
            out.append((label, number(p, "dynamic_uj", where=at), static))
        return out

    parts = [(f"{label} ops", d, s) for label, d, s in parts_of("units", False)]
    parts += parts_of("caches", True)
    parts.append(("crossbars", sum(d for _, d, _ in parts_of("links", False)), 0.0))
    parts.append(("DRAM commands", number(e, "dram.dynamic_uj", where=where), 0.0))
    parts.append(("DRAM background", 0.0, number(e, "dram.static_uj", where=where)))
    types = field(e, "ray_types", where=where)
    if not isinstance(types, dict) or not all(
        isinstance(t, dict) and is_number(t.get("uj")) and is_number(t.get("nj_per_ray"))
        for t in types.values()
    ):
        raise InputError(f"{where}: field 'ray_types' is not a map of {{uj, nj_per_ray}}")
    order = ["primary", "reflection", "shadow", "nee", "bounce"]  # a ray's life; others after
    names = sorted(types, key=lambda n: (order.index(n) if n in order else len(order), n))
    rays = [(n, float(types[n]["uj"]), float(types[n]["nj_per_ray"])) for n in names]
    totals = dict(
        node=field(e, "node", where=where),
        total=number(e, "total_uj", where=where),
        power=number(e, "average_power_w", where=where),
    )
    return parts, rays, totals


def plot_energy(r, energy, path, written):
    """Left: each part's dynamic and static energy (uJ); right: each ray type's share (uJ), its
    energy per ray written at the bar."""
    parts, rays, totals = energy
    fig, (left, right) = plt.subplots(
        1, 2, figsize=(12, 0.32 * len(parts) + 2.5), layout="constrained", width_ratios=[3, 2]
    )
    y = range(len(parts))
    left.barh(y, [d for _, d, _ in parts], color=DYNAMIC, label="dynamic")
    left.barh(
        y, [s for _, _, s in parts], left=[d for _, d, _ in parts], color=STATIC, label="static"
    )
    left.set_yticks(list(y), [p[0] for p in parts])
    left.invert_yaxis()
    left.set_xlabel("energy per frame (uJ)")
    left.grid(axis="x", alpha=0.3)
    left.legend(loc="upper right", fontsize=9)
    yr = range(len(rays))
    right.barh(yr, [uj for _, uj, _ in rays], color="tab:green")
    for yi, (_, uj, nj) in zip(yr, rays):
        right.text(uj, yi, f" {nj:.1f} nJ/ray", va="center", fontsize=8)
    right.set_yticks(list(yr), [t[0] for t in rays])
    right.invert_yaxis()
    right.set_xlabel("energy per frame by ray type (uJ)")
    right.grid(axis="x", alpha=0.3)
    fig.suptitle(
        f"{r['title']}\nenergy ({totals['node']}): {totals['total']:,.1f} uJ, "
        f"{totals['power']:.2f} W on average",
        fontsize=10,
    )
    save(fig, path, written)
