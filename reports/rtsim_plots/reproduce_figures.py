"""The paper's figures beside ours: reproduce_culling.png and reproduce_time.png
(plots.py reproduce)."""

import math
import os
import textwrap

import numpy as np

from rtsim_plots.common import InputError, field, is_number, load_parsed, number, pct, plt, save
from rtsim_plots.files import REPRODUCTION_JSON
from rtsim_plots.sweep_figures import check_schema


# One colour per source, the same in both figures; the paper's figures are the reference, in gray.
SOURCES = [
    ("paper", "paper (published)", "tab:gray"),
    ("ours_paper", "ours, paper's method", "tab:orange"),
    ("ours_paper_contained", "ours, paper's method, contained", "tab:green"),
    ("ours_exact", "ours, exact mode", "tab:blue"),
]
BAR = 0.8 / len(SOURCES)  # bar width: the sources side by side in 0.8 of a slot


def bar_offset(k):
    return (k - (len(SOURCES) - 1) / 2) * BAR


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


def ms_intervals(run, where):
    """A sampled run's frame times' 95% half-intervals [all, shadow] in ms; None for a full run."""
    if "frame_ms_all_ci95" not in run:
        return None
    return [number(run, f"frame_ms_{k}_ci95", where) for k in ("all", "shadow")]


def sampled_intervals(s, key, run, where):
    """A sampled culling run's intervals: its frame times' (ms) and its reductions' (points of
    %); none for a full run."""
    s["ms_ci"][key] = ms_intervals(run, where)
    red = field(run, "reduction", None, where=where)
    if red is not None:
        s["time_ci"][key] = [
            number(red, f"{k}.ci95_pt", where) if k in red else None for k in ("all", "shadow")
        ]


def parse_reproduction(rep):
    """Per scene, the percentages both figures need, checked up front so bad input writes no
    file."""
    where = REPRODUCTION_JSON
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
        s.update(time_ci={}, ms_ci={})  # ours, sampled: the 95% half-intervals
        paper = field(sc, "paper", None, where=w)
        if paper is None:
            s["missing"].append("the paper's figures")
        else:
            wp = f"{w}.paper"
            per_light = number(paper, "shadow_rays_per_light", wp)
            s["rays"]["paper"] = [pct(c, per_light) for c in numbers(paper, "culled_rays", wp)]
            leaves = number(paper, "leaves", wp)
            s["leaves"]["paper"] = [pct(c, leaves) for c in numbers(paper, "culled_leaves", wp)]
            ms = {
                k: number(paper, f"ms.{k}", wp)
                for k in ("all_on", "all_off", "shadow_on", "shadow_off")
            }
            s["ms"]["paper"] = ms
            s["time"]["paper"] = [
                reduction_pct(ms[f"{k}_on"], ms[f"{k}_off"]) for k in ("all", "shadow")
            ]
        ours = field(sc, "ours", {}, where=w)
        if not isinstance(ours, dict):
            raise InputError(f"{w}: field 'ours' is not an object")
        off = ours.get("off")
        if off is not None:
            s["ms_ci"]["off"] = ms_intervals(off, f"{w}.ours.off")
            off = [number(off, f"frame_ms_{k}", f"{w}.ours.off") for k in ("all", "shadow")]
        else:
            s["missing"].append("our culling-off run")
        for var, key, label in (
            ("paper", "ours_paper", "our paper's-method run"),
            (
                "paper-contained",
                "ours_paper_contained",
                "our paper's-method run with the contained reading",
            ),
            ("exact", "ours_exact", "our exact-mode run"),
        ):
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
            sampled_intervals(s, key, o, wo)
            px = o.get("pixels_shadow_differs_from_off")
            if px is not None:
                if not is_number(px):
                    raise InputError(
                        f"{wo}: field 'pixels_shadow_differs_from_off' is not a number"
                    )
                s["pixels"][key] = px
        s["ms"]["off"] = off
        out.append(s)
    return out


def fmt_pct(v):
    # Two decimals below 1 %: the paper's bunny figures (0.01 % of rays, 0.07 % of time) must not
    # read as 0.
    if v == 0:
        return "0"
    if abs(v) < 0.005:
        return "<0.01" if v > 0 else ">-0.01"
    return f"{v:.2f}" if abs(v) < 1 else f"{v:.1f}"


def value_labels(ax, xs, values, fmt, rotation=0, fontsize=8, errs=None):
    """Value at the end of each bar, offset in points so it works on any scale; "n/a" where unknown
    (None). With errs (error bars' half-lengths), beyond the bar's error bar."""
    for x, v, e in zip(xs, values, errs or [0] * len(values)):
        if v is None:
            ax.annotate(
                "n/a",
                (x, 0),
                xytext=(0, 2),
                textcoords="offset points",
                ha="center",
                va="bottom",
                fontsize=fontsize - 1,
                color="dimgray",
                rotation=90,
            )
        else:
            down = v < 0
            ax.annotate(
                fmt(v),
                (x, v - (e or 0) if down else v + (e or 0)),
                xytext=(0, -2 if down else 2),
                textcoords="offset points",
                ha="center",
                va="top" if down else "bottom",
                fontsize=fontsize,
                rotation=rotation,
            )


def legend_strip(fig):
    # A subfigure of its own: matplotlib 3.6's constrained layout leaves room for no figure legend.
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for _, _, c in SOURCES]
    fig.legend(
        handles, [label for _, label, _ in SOURCES], loc="center", ncol=len(SOURCES), frameon=False
    )


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
    ax.text(
        0.5,
        0.5,
        f"{REPRODUCTION_JSON} lists no scene: no run finished.",
        ha="center",
        va="center",
        fontsize=13,
    )


def panel_title(ax, s, extra=""):
    title = s["title"]
    if s["missing"]:
        # Wrapped: a scene missing everything would otherwise run into its neighbour's title.
        title += "\n" + textwrap.fill("missing: " + "; ".join(s["missing"]), 60)
    ax.set_title(title + extra, fontsize=10)


def nothing_here(ax):
    ax.text(
        0.5,
        0.5,
        "nothing to compare",
        transform=ax.transAxes,
        ha="center",
        va="center",
        color="dimgray",
    )
    ax.set_yticks([])


def per_light_panel(ax, s, kind):
    # The scene's own light count (the larger of the paper's and ours), not the widest scene's: no
    # rows of n/a.
    nlights = max([1] + [len(v) for k in ("rays", "leaves") for v in s[k].values()])
    x = np.arange(nlights)
    top = 0.0
    for k, (key, _, colour) in enumerate(SOURCES):
        if key not in s[kind]:
            # The whole source is missing: said in the panel title, not with n/a on every light.
            continue
        vals = s[kind][key]
        vals = [vals[i] if i < len(vals) else None for i in range(nlights)]
        xs = x + bar_offset(k)
        ax.bar(xs, [v or 0 for v in vals], BAR, color=colour)
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
        items = ", ".join(
            f"{label.split(', ', 1)[1]} {s['pixels'][key]:,.0f}"
            for key, label, _ in SOURCES
            if key in s["pixels"]
        )
        head = "shadow pixels changed by culling:"
        # A long list goes to a line of its own: break between, not inside.
        extra = f"\n{head}" + ("\n" if len(head) + len(items) > 60 else " ") + items
    panel_title(ax, s, extra)


def plot_reproduce_culling(scenes, path, written):
    n = len(scenes)
    nlights = max(
        [1] + [len(v) for s in scenes for kind in ("rays", "leaves") for v in s[kind].values()]
    )
    ncols, nrows = min(REPRO_COLS, max(n, 1)), math.ceil(max(n, 1) / REPRO_COLS)
    width = max(4.8, 0.7 * nlights + 1.4)
    fig = plt.figure(
        figsize=(max(REPRO_MIN_WIDTH, width * ncols + 0.4), 2 * nrows * 3.9 + 1.3),
        layout="constrained",
    )
    fig.suptitle(
        "LVB culling per light: the paper vs ours\n"
        "lights go by index: the paper did not publish its light positions, "
        "ours are the scene files' own"
    )
    if not n:
        nothing_to_plot(fig)
        save(fig, path, written)
        return
    top, rays_fig, leaves_fig = fig.subfigures(3, 1, height_ratios=[0.35, 3.9 * nrows, 3.9 * nrows])
    legend_strip(top)
    rays_fig.suptitle(
        "shadow rays culled (% of the shadow rays to that light)", fontsize=11, fontweight="bold"
    )
    leaves_fig.suptitle(
        "leaves culled — the denominators differ: paper: % of all leaves; "
        "ours: % of non-empty leaves",
        fontsize=11,
        fontweight="bold",
    )
    for sub, kind, ylabel in (
        (rays_fig, "rays", "shadow rays culled (%)"),
        (leaves_fig, "leaves", "leaves culled (%)"),
    ):
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
        lines.append(
            f"paper: all {p['all_off']:.2f} → {p['all_on']:.2f}, shadow {p['shadow_off']:.2f} → "
            f"{p['shadow_on']:.2f} ms"
        )
    off = s["ms"]["off"]

    def ms(v, ci, i):  # a sampled run's time with its interval
        return f"{v[i]:.3f}" + (f" ± {ci[i]:.3f}" if ci else "")

    for key, label, _ in SOURCES[1:]:
        on, on_ci, off_ci = s["ms"].get(key), s["ms_ci"].get(key), s["ms_ci"].get("off")
        if on:
            pairs = [
                f"{ms(off, off_ci, i)} → {ms(on, on_ci, i)}" if off else f"? → {ms(on, on_ci, i)}"
                for i in range(2)
            ]
            # With intervals a line would run into the next panel: all and shadow on two.
            sep = ",\n    " if on_ci or off_ci else ", "
            lines.append(f"{label}: all {pairs[0]}{sep}shadow {pairs[1]} ms")
    return "frame time, culling off → on:\n" + "\n".join(lines) if lines else "no frame times"


def plot_reproduce_time(scenes, path, written):
    n = len(scenes)
    ncols, nrows = min(REPRO_COLS, max(n, 1)), math.ceil(max(n, 1) / REPRO_COLS)
    fig = plt.figure(
        figsize=(max(REPRO_MIN_WIDTH, 5.2 * ncols + 0.4), nrows * 5.4 + 1.5), layout="constrained"
    )
    sampled = any(s["time_ci"] for s in scenes)
    fig.suptitle(
        "Frame-time reduction with LVB culling, (off − on) / off\n"
        "absolute times differ (the paper's simulator and ours model the hardware differently),\n"
        "so the reductions are compared"
        + (
            "\nerror bars on ours: sampled, 95% interval (paired unit by unit where both runs "
            "share the plan)"
            if sampled
            else ""
        )
    )
    if not n:
        nothing_to_plot(fig)
        save(fig, path, written)
        return
    top, main = fig.subfigures(2, 1, height_ratios=[0.35, 5.4 * nrows])  # legend strip, panels
    legend_strip(top)
    x = np.arange(2)
    for k, (ax, s) in enumerate(zip(scene_grid(main, n), scenes)):
        vals_all = []
        for j, (key, _, colour) in enumerate(SOURCES):
            vals = s["time"].get(key, [None, None])
            xs = x + bar_offset(j)
            errs = s["time_ci"].get(key)
            if errs is None:  # the paper's, or a full run's: exact
                ax.bar(xs, [v or 0 for v in vals], BAR, color=colour)
                value_labels(ax, xs, vals, lambda v: fmt_pct(v) + " %")
            else:  # an estimate: with its 95% interval
                errs = [e or 0 for e in errs]
                ax.bar(xs, [v or 0 for v in vals], BAR, color=colour, yerr=errs, capsize=3)
                value_labels(ax, xs, vals, lambda v: fmt_pct(v) + " %", errs=errs)
                vals_all += [v + e for v, e in zip(vals, errs) if v is not None]
                vals_all += [v - e for v, e in zip(vals, errs) if v is not None]
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
    scenes = load_parsed(folder, REPRODUCTION_JSON, parse_reproduction)
    plot_reproduce_culling(scenes, os.path.join(folder, "reproduce_culling.png"), written)
    plot_reproduce_time(scenes, os.path.join(folder, "reproduce_time.png"), written)
