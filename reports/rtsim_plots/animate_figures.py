"""Figures over an animation's time, frames.gif and summary.md (plots.py animate)."""

import math
import os
import re

from rtsim_plots.common import InputError, plt, read_csv, save, write_atomically, write_text
from rtsim_plots.files import FRAMES_CSV, HOST_CSV


def series(rows, key):
    return [r.get(key) if r.get(key) is not None else math.nan for r in rows]


def time_axis(ax, title):
    ax.set_xlabel("scene time (s)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)


def write_gif(folder, times, written):
    from PIL import Image  # Debian's python3-pil, which matplotlib depends on

    frames_dir = os.path.join(folder, "frames")
    names = (
        sorted(n for n in os.listdir(frames_dir) if re.fullmatch(r"frame_\d{4}\.png", n))
        if os.path.isdir(frames_dir)
        else []
    )
    if not names:
        return
    images = [Image.open(os.path.join(frames_dir, n)).convert("RGB") for n in names]
    # One frame per sample at the scene's pace (its time step in seconds), at least 50 ms.
    step = (times[-1] - times[0]) / (len(times) - 1) if len(times) > 1 else 0.1
    duration = max(50, int(round(step * 1000)))
    write_atomically(
        os.path.join(folder, "frames.gif"),
        lambda tmp: images[0].save(
            tmp, format="GIF", save_all=True, append_images=images[1:], duration=duration, loop=0
        ),
        written,
    )


def animate(folder, written):
    rows = read_csv(folder, FRAMES_CSV)
    host = {r["time"]: r for r in read_csv(folder, HOST_CSV)}
    if not rows:
        raise InputError(os.path.join(folder, FRAMES_CSV) + ": no frames")
    t = [r["time"] for r in rows]
    out = os.path.join(folder, "plots")
    os.makedirs(out, exist_ok=True)

    fig, ax = plt.subplots(figsize=(7, 4))
    for key, label, colour in (
        ("cycles_off", "culling off", "tab:gray"),
        ("cycles_on", "culling on", "tab:blue"),
    ):
        ax.plot(t, series(rows, key), marker="o", ms=3, label=label, color=colour)
    ax.set_ylabel("cycles per frame")
    ax.set_ylim(bottom=0)
    ax.legend()
    time_axis(ax, "Simulated cycles per frame")
    save(fig, os.path.join(out, "animate_cycles.png"), written)

    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(
        t,
        [100 * v for v in series(rows, "culled_share")],
        marker="o",
        ms=3,
        label="shadow rays culled",
    )
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
    for key, label in (
        ("lvb_nodes_visited", "kd-tree nodes visited"),
        ("lvb_region_tests", "region (box) tests"),
        ("lvb_pair_tests", "triangle-pair tests"),
    ):
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


def summary_table(rows, host):
    """Per frame, the figures of a summary row (None where a column is empty)."""

    def ratio(a, b):
        return a / b if a is not None and b else None

    table = []
    for r in rows:
        h = host.get(r["time"], {})
        saved = (
            (r["cycles_off"] - r["cycles_on"])
            if r.get("cycles_off") is not None and r.get("cycles_on") is not None
            else None
        )
        build = (
            (r["lvb_region_tests"] + r["lvb_pair_tests"])
            if r.get("lvb_region_tests") is not None
            else None
        )
        lazy = (
            (r["lazy_region_tests"] + r["lazy_pair_tests"] + r["lazy_dirty_tests"])
            if r.get("lazy_region_tests") is not None
            else None
        )
        table.append(
            {
                "time": r["time"],
                "saved": saved,
                "share": r.get("culled_share"),
                "build": build,
                "pays": ratio(saved, build),
                "lvb_s": h.get("lvb_seconds"),
                "kd_s": h.get("kdtree_seconds"),
                "dirty": ratio(r.get("lazy_dirty_pairs"), r.get("lazy_pairs")),
                "lazy": lazy,
                "lazy_share": ratio(lazy, build),
                "lazy_pays": ratio(saved, lazy),
                "off": r.get("cycles_off"),
                "on": r.get("cycles_on"),
            }
        )
    return table


def animate_summary(rows, host):
    """Markdown: a row per frame, then the medians. Builder cycles assume one test (region or pair)
    per cycle."""

    def cell(v, fmt="{:,.0f}"):
        return "" if v is None or (isinstance(v, float) and math.isnan(v)) else fmt.format(v)

    table = summary_table(rows, host)
    head = (
        "| time | cycles off | cycles on | saved cycles | shadow rays culled "
        "| LVB tests (builder cycles) | saved / LVB tests | LVB s | kd-tree s | lazy: dirty pairs "
        "| lazy: tests | lazy / full | saved / lazy tests |"
    )
    lines = [
        "# Culling against its recomputation, per frame",
        "",
        "Builder cycles: the LVB's region and pair tests at one test per cycle; lazy tests add the "
        "dirty tests that find the pairs to redo. Host seconds vary from run to run (host.csv).",
        "",
        head,
        "|" + "---|" * 13,
    ]
    pct_fmt = "{:.1%}"
    for x in table:
        lines.append(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |".format(
                f"{x['time']:g}",
                cell(x["off"]),
                cell(x["on"]),
                cell(x["saved"]),
                cell(x["share"], pct_fmt),
                cell(x["build"]),
                cell(x["pays"], "{:.4f}"),
                cell(x["lvb_s"], "{:.2f}"),
                cell(x["kd_s"], "{:.2f}"),
                cell(x["dirty"], pct_fmt),
                cell(x["lazy"]),
                cell(x["lazy_share"], pct_fmt),
                cell(x["lazy_pays"], "{:.4f}"),
            )
        )
    m = {k: median([x[k] for x in table]) for k in table[0] if k != "time"}
    lines.append(
        "| **median** | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |".format(
            cell(m["off"]),
            cell(m["on"]),
            cell(m["saved"]),
            cell(m["share"], pct_fmt),
            cell(m["build"]),
            cell(m["pays"], "{:.4f}"),
            cell(m["lvb_s"], "{:.2f}"),
            cell(m["kd_s"], "{:.2f}"),
            cell(m["dirty"], pct_fmt),
            cell(m["lazy"]),
            cell(m["lazy_share"], pct_fmt),
            cell(m["lazy_pays"], "{:.4f}"),
        )
    )
    return "\n".join(lines) + "\n"
