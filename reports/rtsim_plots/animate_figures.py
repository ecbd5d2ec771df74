"""Figures over an animation's time and frames.gif (plots.py animate). rtsim animate writes the
tables, frames.csv, host.csv and summary.md, itself (reports/animation_tables.h)."""

import math
import os
import re

from rtsim_plots.common import InputError, plt, read_csv, save, write_atomically
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
    sampled = "cycles_on_ci95" in rows[0]  # rtsim animate --sample: estimates with intervals
    for key, label, colour in (
        ("cycles_off", "culling off", "tab:gray"),
        ("cycles_on", "culling on", "tab:blue"),
    ):
        if sampled:
            ax.errorbar(
                t,
                series(rows, key),
                yerr=series(rows, key + "_ci95"),
                marker="o",
                ms=3,
                capsize=2,
                label=label,
                color=colour,
            )
        else:
            ax.plot(t, series(rows, key), marker="o", ms=3, label=label, color=colour)
    ax.set_ylabel("cycles per frame")
    ax.set_ylim(bottom=0)
    ax.legend()
    time_axis(
        ax,
        "Simulated cycles per frame" + (" (sampled, error bars: 95% interval)" if sampled else ""),
    )
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
