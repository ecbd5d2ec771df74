#!/usr/bin/env python3
"""The figures of a sweep (plots.py sweep, reports/rtsim_plots/sweep_figures.py) show the rows of
its results.json: one figure per metric and varying axis, one line per combination of the other
axes, each point the mean of the rows at that x, compared with what the test computes from the
rows it wrote.
Usage: sweep_figures_test.py SOURCE_DIR"""

import itertools
import random

import figure_check as fc

sweep_figures = fc.module("sweep_figures")
SIZE, LVB = "hw.trv.l1.size_kb", "run.lvb"
METRICS = ["cycles_total", "trv_l1_hit_rate"]


def results(rows, axes, name="cachetest"):
    """results.json as `rtsim sweep` writes it: rows in the order their points finished."""
    for i, row in enumerate(rows):
        row.setdefault("point", i)
        row.setdefault("id", f"p{i:04d}")
    done = rows[:]
    random.Random(len(rows)).shuffle(done)
    return {
        "schema": "rtsim-sweep/1",
        "name": name,
        "axes": axes,
        "metrics": METRICS,
        "points": len(rows),
        "rows": done,
        "failed": 0,
    }


def expected_lines(rows, metric, axis, other):
    """label -> (x, mean of the metric at x) of each value of the other axis, in point order; x is
    the axis value when it is a number, else its index in first-seen order."""
    values = list(dict.fromkeys(str(r[axis]) for r in rows))
    lines = {}
    for row in rows:
        points = lines.setdefault(f"{other}={row[other]}", {})
        if row[metric] is not None:
            numeric = isinstance(row[axis], int) and not isinstance(row[axis], bool)
            x = row[axis] if numeric else values.index(str(row[axis]))
            points.setdefault(float(x), []).append(row[metric])
    return {
        label: (sorted(p), [sum(p[x]) / len(p[x]) for x in sorted(p)]) for label, p in lines.items()
    }


class SweepFigures(fc.FigureTest):
    def write_rows(self):
        rng = random.Random(41)
        rows = []
        for size, lvb in itertools.product([4, 8, 16], [False, True]):
            rows.append({"scene": "city", SIZE: size, LVB: lvb})
        rows.append({"scene": "city", SIZE: 8, LVB: True})  # a repeated point: averaged
        for row in rows:
            row["cycles_total"] = rng.randrange(10**5, 10**7)
            row["trv_l1_hit_rate"] = rng.random()
        rows[0]["trv_l1_hit_rate"] = None  # a metric a point could not report: no marker
        self.write_json("results.json", results(rows, [SIZE, LVB]))
        return rows

    def test_each_line_is_the_mean_of_the_rows_at_each_x(self):
        rows = self.write_rows()
        figures = self.draw(sweep_figures.sweep)
        names = [f"plots/{m}_vs_{a}.png" for m in METRICS for a in (SIZE, LVB)]
        self.assertEqual(sorted(figures), sorted(names))
        for metric, (axis, other) in itertools.product(METRICS, [(SIZE, LVB), (LVB, SIZE)]):
            ax = figures[f"plots/{metric}_vs_{axis}.png"].axes[0]
            want = expected_lines(rows, metric, axis, other)
            got = fc.series(ax)
            self.assertEqual(list(got), list(want), f"{metric} vs {axis}: the series")
            for label, (x, y) in want.items():
                self.assertNumbers(got[label][0], x, f"{metric} vs {axis}, {label}: x")
                self.assertNumbers(got[label][1], y, f"{metric} vs {axis}, {label}: y")
            self.assertTrue(ax.get_xlabel().startswith(axis), ax.get_xlabel())
            self.assertTrue(ax.get_ylabel().startswith(metric), ax.get_ylabel())
            self.assertEqual(
                ax.get_title(), f"{metric} vs {axis}\nsweep cachetest, scene city, 7 points"
            )
        size_ax = figures[f"plots/cycles_total_vs_{SIZE}.png"].axes[0]
        self.assertEqual(size_ax.get_xscale(), "log", "sizes in powers of 2")
        self.assertEqual(size_ax.get_xlabel(), f"{SIZE} (KB) (log₂ scale)")
        self.assertEqual(fc.xticks(size_ax), ["4", "8", "16"])
        self.assertEqual(
            fc.xticks(figures[f"plots/cycles_total_vs_{LVB}.png"].axes[0]), ["False", "True"]
        )
        self.assertNoMarkdown()  # plots/index.md is the sweep's (reports/sweep_index.cpp)

    def test_energy_and_time_ring_each_series_optimum(self):
        # Energy falls then rises with the size; time only falls: the optima differ.
        energy = {4: 120.0, 8: 100.0, 16: 110.0}
        time = {4: 3.0, 8: 2.0, 16: 1.5}
        rows = []
        for size, lvb in itertools.product([4, 8, 16], [False, True]):
            scale = 0.9 if lvb else 1.0
            rows.append(
                {
                    "scene": "city",
                    SIZE: size,
                    LVB: lvb,
                    "energy_uj": energy[size] * scale,
                    "frame_ms_all": time[size] * scale,
                }
            )
        doc = results(rows, [SIZE, LVB])
        doc["metrics"] = ["energy_uj", "frame_ms_all"]
        self.write_json("results.json", doc)
        figures = self.draw(sweep_figures.sweep)
        top, bottom = figures[f"plots/energy_and_time_vs_{SIZE}.png"].axes
        for ax, what, best in ((top, "energy", 8), (bottom, "time", 16)):
            rings = [line for line in ax.get_lines() if not line.get_label().startswith("_")]
            self.assertEqual(
                [r.get_label() for r in rings],
                [f"{LVB}={v}: {what}-optimal at {best}" for v in (False, True)],
            )
            for ring, scale in zip(rings, (1.0, 0.9)):
                want = (energy if what == "energy" else time)[best] * scale
                self.assertNumbers(list(ring.get_xdata()), [best], what)
                self.assertNumbers(list(ring.get_ydata()), [want], what)
        self.assertEqual(bottom.get_xscale(), "log", "sizes in powers of 2")

    def test_several_scenes_make_the_scene_an_axis(self):
        rng = random.Random(42)
        rows = [
            {
                "scene": scene,
                SIZE: size,
                LVB: True,
                "cycles_total": rng.randrange(10**6),
                "trv_l1_hit_rate": None,
            }
            for scene, size in itertools.product(["city", "robots", "bunny"], [4, 8])
        ]
        self.write_json("results.json", results(rows, [SIZE, LVB]))
        figures = self.draw(sweep_figures.sweep)
        names = [f"plots/{m}_vs_{a}.png" for m in METRICS for a in (SIZE, "scene")]
        self.assertEqual(sorted(figures), sorted(names), "run.lvb does not vary: no figure")
        ax = figures["plots/cycles_total_vs_scene.png"].axes[0]
        self.assertEqual(fc.xticks(ax), ["city", "robots", "bunny"])
        want = expected_lines(rows, "cycles_total", "scene", SIZE)
        got = fc.series(ax)
        self.assertEqual(list(got), list(want))
        for label, (x, y) in want.items():
            self.assertNumbers(got[label][0], x, label)
            self.assertNumbers(got[label][1], y, label)
        # A metric with no value anywhere: no line, and the figure says so.
        empty = figures["plots/trv_l1_hit_rate_vs_scene.png"].axes[0]
        self.assertEqual(fc.series(empty), {})
        self.assertIn("no values yet", fc.texts(empty))

    def test_sampled_rows_draw_each_estimate_with_its_interval(self):
        rows = self.write_rows()
        for i, row in enumerate(rows):
            row.update(sampled=True, cycles_total_ci95=1000.0 * (i + 1))
        self.write_json("results.json", results(rows, [SIZE, LVB]))
        figures = self.draw(sweep_figures.sweep)
        ax = figures[f"plots/cycles_total_vs_{SIZE}.png"].axes[0]
        self.assertIn("error bars: sampled, 95% interval", ax.get_title())
        want = expected_lines(rows, "cycles_total", SIZE, LVB)
        bars = {c.get_label(): c for c in ax.containers}
        self.assertEqual(sorted(bars), sorted(want))
        for label, (xs, ys) in want.items():
            # The mean of repeated points has the root of the squares over their number.
            cis = []
            for x in xs:
                at = [r for r in rows if r[SIZE] == x and f"{LVB}={r[LVB]}" == label]
                cis.append(sum(r["cycles_total_ci95"] ** 2 for r in at) ** 0.5 / len(at))
            lows, highs = fc.error_bars(bars[label])
            self.assertNumbers(lows, [y - c for y, c in zip(ys, cis)], f"{label}: lows")
            self.assertNumbers(highs, [y + c for y, c in zip(ys, cis)], f"{label}: highs")
        # A metric without an interval (a rate) is drawn as before.
        rate = figures[f"plots/trv_l1_hit_rate_vs_{SIZE}.png"].axes[0]
        self.assertEqual(rate.containers, [])
        self.assertNotIn("sampled", rate.get_title())

    def test_full_rows_draw_no_error_bars(self):
        self.write_rows()
        figures = self.draw(sweep_figures.sweep)
        for name, fig in figures.items():
            self.assertEqual(fig.axes[0].containers, [], name)
            self.assertNotIn("sampled", fig.axes[0].get_title(), name)


if __name__ == "__main__":
    fc.main()
