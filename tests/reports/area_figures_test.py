#!/usr/bin/env python3
"""The area-light figure (plots.py area, reports/rtsim_plots/area_figures.py) shows, per scene and
sample count, the frame-time reduction of culling on against off in the sweep's results.json: each
line's points are compared with (cycles off - cycles on) / cycles off of the rows the test wrote.
It writes no Markdown: area_lights.md is the sweep's (reports/area_report.cpp, tested by
tests/reports/test_markdown_reports.cpp).
Usage: area_figures_test.py SOURCE_DIR"""

import itertools
import random

import figure_check as fc

area_figures = fc.module("area_figures")
SAMPLES = "scene.lights.area_from_points.samples"
SCENES, COUNTS = ["robots", "bunny"], [1, 4, 16]


def sweep_rows(rng, slower=None):
    """A row per scene, sample count and culling off/on, as `rtsim sweep` writes them; culling on
    makes the frame slower at the (scene, samples) of `slower`."""
    rows = []
    for i, (scene, n, lvb) in enumerate(itertools.product(SCENES, COUNTS, [False, True])):
        row = {"point": i, "id": f"p{i:04d}", "scene": scene, SAMPLES: n, "run.lvb": lvb}
        row["rays_shadow"] = rng.randrange(10**4, 10**6)
        row["shadow_culled"] = rng.randrange(0, row["rays_shadow"])
        row["shadow_culled_rate"] = row["shadow_culled"] / row["rays_shadow"]
        if lvb:
            off = rows[-1]["cycles_total"]
            row["cycles_total"] = (
                off + 1000 if (scene, n) == slower else rng.randrange(off // 2, off)
            )
        else:
            row["cycles_total"] = rng.randrange(10**6, 10**7)
        rows.append(row)
    return rows


class AreaFigure(fc.FigureTest):
    def draw_rows(
        self,
        rows,
        metrics=("cycles_total", "rays_shadow", "shadow_culled", "shadow_culled_rate"),
        **extra,
    ):
        """The area figure of a sweep's results.json with `rows` (and `extra` keys)."""
        self.write_json(
            "results.json",
            {
                "schema": "rtsim-sweep/1",
                "name": "area",
                "axes": [SAMPLES, "run.lvb"],
                "metrics": list(metrics),
                "points": len(rows),
                "rows": rows,
                "failed": [],
                **extra,
            },
        )
        figures = self.draw(area_figures.area)
        self.assertEqual(list(figures), ["plots/area_reduction.png"])
        self.assertNoMarkdown()  # area_lights.md is the sweep's (reports/area_report.cpp)
        return figures["plots/area_reduction.png"].axes[0]

    def expect_reductions(self, ax, rows):
        cycles = {(r["scene"], r[SAMPLES], r["run.lvb"]): r["cycles_total"] for r in rows}
        got = fc.series(ax)
        self.assertEqual(sorted(got), sorted(SCENES), "a line per scene")
        for scene in SCENES:
            off = [cycles[(scene, n, False)] for n in COUNTS]
            on = [cycles[(scene, n, True)] for n in COUNTS]
            self.assertNumbers(got[scene][0], COUNTS, f"{scene}: samples")
            want = [100.0 * (a - b) / a for a, b in zip(off, on)]
            self.assertNumbers(got[scene][1], want, f"{scene}: reduction (%)")
        self.assertEqual(ax.get_xlabel(), "shadow rays per hit and light (samples)")
        self.assertEqual(ax.get_ylabel(), "frame-time reduction with culling (%)")
        self.assertEqual(ax.get_xscale(), "log")
        self.assertEqual(ax.get_title(), "Culling and area lights (sweep area)")

    def test_each_line_is_a_scene_s_reduction_per_sample_count(self):
        rows = sweep_rows(random.Random(43))
        ax = self.draw_rows(rows)
        self.expect_reductions(ax, rows)
        self.assertEqual(ax.get_ylim()[0], 0, "no frame slower with culling: the axis starts at 0")

    def test_a_slower_frame_shows_below_zero(self):
        rows = sweep_rows(random.Random(44), slower=("bunny", 4))
        ax = self.draw_rows(rows)
        self.expect_reductions(ax, rows)
        self.assertLess(min(fc.series(ax)["bunny"][1]), 0)
        zero = [line for line in ax.get_lines() if line.get_label().startswith("_")]
        self.assertEqual([list(line.get_ydata()) for line in zero], [[0, 0]], "the zero line drawn")

    def test_a_cell_without_both_runs_is_left_out(self):
        rows = sweep_rows(random.Random(45))
        rows = [
            r for r in rows if not (r["scene"] == "robots" and r[SAMPLES] == 4 and r["run.lvb"])
        ]
        ax = self.draw_rows(rows)
        self.assertNumbers(fc.series(ax)["robots"][0], [1, 16], "robots: samples with both runs")

    def test_sampled_rows_draw_each_reduction_with_its_interval(self):
        rows = sweep_rows(random.Random(47))
        for r in rows:
            r.update(sampled=True, cycles_total_ci95=0.01 * r["cycles_total"])
        ax = self.draw_rows(
            rows, ["cycles_total"], sampled_columns=["sampled", "cycles_total_ci95"]
        )
        cycles = {(r["scene"], r[SAMPLES], r["run.lvb"]): r["cycles_total"] for r in rows}
        bars = [c for c in ax.containers if not isinstance(c, fc.BarContainer)]
        self.assertEqual(sorted(b.get_label() for b in bars), sorted(SCENES))
        for bar in bars:
            scene = bar.get_label()
            off = [cycles[(scene, n, False)] for n in COUNTS]
            on = [cycles[(scene, n, True)] for n in COUNTS]
            red = [100.0 * (a - b) / a for a, b in zip(off, on)]
            # 1 % on each: the ratio's relative error is 1 % times the root of 2.
            ci = [100.0 * b / a * 0.01 * 2**0.5 for a, b in zip(off, on)]
            lows, highs = fc.error_bars(bar)
            self.assertNumbers(lows, [r - c for r, c in zip(red, ci)], scene)
            self.assertNumbers(highs, [r + c for r, c in zip(red, ci)], scene)
        self.assertIn("sampled, 95% interval", ax.get_title())


if __name__ == "__main__":
    fc.main()
