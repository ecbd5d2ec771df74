#!/usr/bin/env python3
"""The figures over an animation's time (plots.py animate, reports/rtsim_plots/animate_figures.py)
show the columns of frames.csv and host.csv: each line's points are compared with the cells the
test wrote (an empty cell is a gap in the line).
Usage: animate_figures_test.py SOURCE_DIR"""

import math
import random

import figure_check as fc

animate_figures = fc.module("animate_figures")
LIGHTS = 2
# The columns `rtsim animate` writes (reports/animation_tables.cpp).
FRAMES = (
    "time,triangles,cycles_off,cycles_on,frame_ms_off,frame_ms_on,saved_ms,shadow_rays,"
    "shadow_rays_culled,culled_share,nonempty_leaves".split(",")
    + [f"culled_leaves_l{i}" for i in range(LIGHTS)]
    + [f"culled_rays_l{i}" for i in range(LIGHTS)]
    + "lvb_nodes_visited,lvb_region_tests,lvb_pair_tests,moved_triangles,lazy_dirty_pairs,"
    "lazy_pairs,lazy_dirty_tests,lazy_nodes_visited,lazy_region_tests,lazy_pair_tests,"
    "check_mismatched_pixels".split(",")
)
HOST = ["time", "kdtree_seconds", "lvb_seconds", "simulate_seconds_off", "simulate_seconds_on"]
TIMES = [0.0, 0.5, 1.0, 1.5]


def frame(rng, t):
    row = {k: rng.randrange(1, 10**6) for k in FRAMES}
    row["time"] = t
    row["shadow_rays_culled"] = rng.randrange(0, row["shadow_rays"])
    row["culled_share"] = row["shadow_rays_culled"] / row["shadow_rays"]
    for i in range(LIGHTS):
        row[f"culled_leaves_l{i}"] = rng.randrange(0, row["nonempty_leaves"])
    return row


def cells(rows, key, scale=1):
    """The column as the figure plots it: NaN for an empty cell."""
    return [scale * r[key] if r.get(key) is not None else math.nan for r in rows]


class AnimateFigures(fc.FigureTest):
    def setUp(self):
        super().setUp()
        rng = random.Random(47)
        self.rows = [frame(rng, t) for t in TIMES]
        self.rows[1]["cycles_off"] = None  # a frame whose culling-off run is missing
        self.write_csv("frames.csv", FRAMES, self.rows)
        self.host = {
            t: {"time": t, "kdtree_seconds": rng.random(), "lvb_seconds": rng.random()}
            for t in TIMES
        }
        del self.host[1.0]  # a frame without host figures
        self.write_csv("host.csv", HOST, self.host.values())
        self.figures = self.draw(animate_figures.animate)
        self.assertEqual(
            sorted(self.figures),
            [
                "plots/animate_culled.png",
                "plots/animate_cycles.png",
                "plots/animate_preprocessing.png",
            ],
        )
        self.assertNoMarkdown()  # summary.md is rtsim animate's (reports/animation_summary.cpp)

    def expect_lines(self, ax, want):
        got = fc.series(ax)
        self.assertEqual(list(got), list(want))
        for label, y in want.items():
            self.assertNumbers(got[label][0], TIMES, f"{label}: time")
            self.assertNumbers(got[label][1], y, label)
        self.assertEqual(ax.get_xlabel(), "scene time (s)")

    def test_cycles_per_frame(self):
        ax = self.figures["plots/animate_cycles.png"].axes[0]
        want = {
            "culling off": cells(self.rows, "cycles_off"),
            "culling on": cells(self.rows, "cycles_on"),
        }
        self.assertTrue(math.isnan(want["culling off"][1]))
        self.expect_lines(ax, want)
        self.assertEqual(ax.get_ylabel(), "cycles per frame")

    def test_culled_shares_per_frame(self):
        ax = self.figures["plots/animate_culled.png"].axes[0]
        leaf_bits = [
            100
            * sum(r[f"culled_leaves_l{i}"] for i in range(LIGHTS))
            / (r["nonempty_leaves"] * LIGHTS)
            for r in self.rows
        ]
        want = {
            "shadow rays culled": cells(self.rows, "culled_share", 100),
            "(leaf, light) bits 0": leaf_bits,
        }
        self.expect_lines(ax, want)
        self.assertEqual(ax.get_ylim(), (0, 100))

    def test_rebuild_time_and_work_per_frame(self):
        host_ax, work_ax = self.figures["plots/animate_preprocessing.png"].axes
        host = [self.host.get(t, {}) for t in TIMES]
        self.expect_lines(
            host_ax,
            {
                "kd-tree build": cells(host, "kdtree_seconds"),
                "LVB (hierarchical)": cells(host, "lvb_seconds"),
            },
        )
        self.assertEqual(host_ax.get_ylabel(), "host seconds")
        work = {
            "kd-tree nodes visited": "lvb_nodes_visited",
            "region (box) tests": "lvb_region_tests",
            "triangle-pair tests": "lvb_pair_tests",
        }
        self.expect_lines(work_ax, {label: cells(self.rows, key) for label, key in work.items()})
        self.assertEqual(work_ax.get_yscale(), "log")
        self.assertEqual(work_ax.get_ylabel(), "count per frame")


class SampledAnimateFigures(fc.FigureTest):
    """rtsim animate --sample: frames.csv ends each row with the runs' 95% half-intervals, and the
    cycles figure draws them as error bars."""

    def setUp(self):
        super().setUp()
        rng = random.Random(48)
        self.rows = [frame(rng, t) for t in TIMES]
        for r in self.rows:
            r["cycles_off_ci95"] = rng.randrange(1, 10**4)
            r["cycles_on_ci95"] = rng.randrange(1, 10**4)
        self.write_csv("frames.csv", FRAMES + ["cycles_off_ci95", "cycles_on_ci95"], self.rows)
        self.write_csv("host.csv", HOST, [{"time": t} for t in TIMES])
        self.figures = self.draw(animate_figures.animate)

    def test_cycles_carry_their_intervals(self):
        ax = self.figures["plots/animate_cycles.png"].axes[0]
        bars = {c.get_label(): fc.error_bars(c) for c in ax.containers}
        self.assertEqual(sorted(bars), ["culling off", "culling on"])
        for label, key in (("culling off", "cycles_off"), ("culling on", "cycles_on")):
            low, high = bars[label]
            self.assertNumbers(low, [r[key] - r[key + "_ci95"] for r in self.rows], label)
            self.assertNumbers(high, [r[key] + r[key + "_ci95"] for r in self.rows], label)
        self.assertIn("sampled", ax.get_title())


if __name__ == "__main__":
    fc.main()
