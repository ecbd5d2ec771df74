#!/usr/bin/env python3
"""The figures of a run directory (plots.py run, reports/rtsim_plots/run_figures.py) show the
numbers of its report.json and culled.npy: each bar, segment and panel is compared with the value
the test computes from the files it wrote.
Usage: run_figures_test.py SOURCE_DIR"""

import math
import os
import random

import numpy as np

import figure_check as fc

run_figures = fc.module("run_figures")
# The unit types a report lists: (label, key, count; None: a unit of its own, not summed).
UNITS = [("ray generator", "raygen", None), ("TRV", "trv", 4), ("LIST", "list", 1)]
UNITS += [("IST", "ist", 2), ("shading", "shading", 1), ("shadow culling", "culling", None)]
STATES = ("busy_cycles", "stalled_cycles", "idle_cycles")


def cache(rng, accesses=None):
    n = rng.randrange(1, 10**6) if accesses is None else accesses
    hits = rng.randrange(0, n + 1)
    return {"accesses": n, "hits": hits, "hit_rate": hits / n if n else 0.0}


def report(rng, width, height, culled_per_light, lvb_on=True):
    """A report.json as `rtsim run` writes it, with the fields the figures read; the shadow rays of
    light i culled culled_per_light[i] times. Light 3 has no shadow rays and LIST's L2 no accesses:
    bars the figures must show as n/a."""
    n = len(culled_per_light)
    shadow = [rng.randrange(c + 1, 10 * c + 100) for c in culled_per_light[:2]] + [0] * (n - 2)
    stats = {"raygen": {k: rng.randrange(1, 10**6) for k in STATES}}
    caches = []
    for label, key, _ in UNITS[1:-1]:
        stats[key] = {"total": {k: rng.randrange(1, 10**6) for k in STATES}}
        stats[key]["l1"] = cache(rng)
        caches.append({"key": f"{key}.l1", "unit": key, "label": label, "level": "L1"})
        if key != "shading":  # no L2 of its own: n/a
            stats[key]["l2"] = cache(rng, 0 if key == "list" else None)
            caches.append({"key": f"{key}.l2", "unit": key, "label": label, "level": "L2"})
    units = [
        {"key": k, "label": n, "count": c or 1, "stats": f"{k}.total" if c else k}
        for n, k, c in UNITS
    ]
    stats["dram"] = {"row_hit_rate": rng.random()}
    lvb = {
        "per_light": [
            {"culled_leaves": c, "nonempty_leaves": c + rng.randrange(1, 1000)}
            for c in (rng.randrange(0, 5000) for _ in range(n))
        ]
    }
    return {
        "scene": {"name": "testcity", "resolution": [width, height]},
        "config": {"run": {"lvb": lvb_on}},
        "units": units,
        "caches": caches,
        "cycles_total": rng.randrange(10**6, 10**8),
        "clock_ghz": 1.0,
        "per_light": [
            {"shadow_rays": s, "culled": c if s else 0} for s, c in zip(shadow, culled_per_light)
        ],
        "lvb": lvb if lvb_on else None,
        "stats": stats,
    }


def pct(part, whole):
    return 100.0 * part / whole if whole else None


class RunFigures(fc.FigureTest):
    def setUp(self):
        super().setUp()
        self.rng = random.Random(40)

    def write_run(self, width=64, height=36, lights=3, lvb_on=True):
        bits = np.random.default_rng(40).integers(0, 2, (lights, height, width), dtype=np.uint16)
        bits[2:] = 0  # lights 3 on have no shadow rays (report), so none culled
        culled = sum(bits[i] << i for i in range(lights)).astype(np.uint16)
        np.save(os.path.join(self.dir, "culled.npy"), culled)
        rep = report(self.rng, width, height, [int(b.sum()) for b in bits], lvb_on)
        self.write_json("report.json", rep)
        return rep, bits

    def test_culling_bars_are_the_culled_shares_per_light(self):
        rep, _ = self.write_run()
        ax = self.draw(run_figures.run)["plot_culling.png"].axes[0]
        leaves, rays = fc.bars(ax)
        self.assertEqual(leaves.get_label(), "leaves culled (% of non-empty leaves)")
        self.assertEqual(rays.get_label(), "shadow rays culled (% of shadow rays)")
        want_leaves = [
            pct(x["culled_leaves"], x["nonempty_leaves"]) for x in rep["lvb"]["per_light"]
        ]
        want_rays = [pct(x["culled"], x["shadow_rays"]) for x in rep["per_light"]]
        self.assertIsNone(want_rays[2], "light 3 has no shadow rays")
        self.assertNumbers(fc.heights(leaves), want_leaves, "leaf bars")
        self.assertNumbers(fc.heights(rays), [v or 0 for v in want_rays], "ray bars")
        # The value above each bar, and n/a where there is none.
        labels = fc.texts(ax)
        for v in want_leaves + want_rays[:2]:
            self.assertIn(f"{v:.1f}", labels)
        self.assertEqual(labels.count("n/a"), 1)
        self.assertEqual(fc.xticks(ax), ["L1", "L2", "L3"])
        self.assertEqual((ax.get_xlabel(), ax.get_ylabel()), ("light", "culled (%)"))
        title = ax.get_title()
        self.assertIn(f"testcity 64×36, LVB on: {rep['cycles_total']:,} cycles", title)
        shadow = sum(x["shadow_rays"] for x in rep["per_light"])
        culled = sum(x["culled"] for x in rep["per_light"])
        self.assertIn(f"{100 * culled / shadow:.1f} % of {shadow:,} shadow rays culled", title)

    def test_culling_off_draws_no_bars(self):
        self.write_run(lvb_on=False)
        fig = self.draw(run_figures.run)["plot_culling.png"]
        self.assertEqual(fc.bars(fig.axes[0]), [])
        self.assertIn("LVB culling was off", " ".join(fc.texts(fig.axes[0])))
        self.assertIn("LVB off", " ".join(fc.texts(fig)))

    def test_time_breakdown_segments_are_the_shares_of_unit_cycles(self):
        rep, _ = self.write_run()
        ax = self.draw(run_figures.run)["plot_time_breakdown.png"].axes[0]
        want = [n + (f" (×{c})" if c else "") for n, k, c in UNITS]
        self.assertEqual(fc.yticks(ax), want)
        colour = fc.legend(ax)
        self.assertEqual(list(colour), ["busy", "stalled", "idle"])
        rows = {}  # unit row -> its segments, left to right
        for container in fc.bars(ax):
            for p in container.patches:
                rows.setdefault(round(p.get_y() + p.get_height() / 2), []).append(p)
        for y, (_, key, summed) in enumerate(UNITS[:-1]):
            cycles = rep["stats"][key]["total"] if summed else rep["stats"][key]
            total = sum(cycles.values())
            shares = [100.0 * cycles[k] / total for k in STATES]
            segments = sorted(rows[y], key=lambda p: p.get_x())
            self.assertNumbers([p.get_width() for p in segments], shares, want[y])
            self.assertNumbers([p.get_x() for p in segments], [0, shares[0], sum(shares[:2])])
            self.assertEqual([tuple(p.get_facecolor()) for p in segments], list(colour.values()))
        # No culling unit in the stats: its row has no bar and says n/a.
        self.assertNotIn(len(UNITS) - 1, rows)
        self.assertIn("n/a", fc.texts(ax))
        self.assertEqual(ax.get_xlim(), (0, 100))

    def test_cache_bars_are_the_hit_rates(self):
        rep, _ = self.write_run()
        ax = self.draw(run_figures.run)["plot_cache_hit_rates.png"].axes[0]
        l1, l2, dram = fc.bars(ax)
        self.assertEqual([c.get_label() for c in (l1, l2, dram)], ["L1", "L2", "DRAM row hits"])

        def rate(key, level):
            c = rep["stats"][key].get(level)
            return 100.0 * c["hit_rate"] if c and c["accesses"] else None

        want = {lvl: [rate(k, lvl) for _, k, _ in UNITS[1:-1]] for lvl in ("l1", "l2")}
        self.assertEqual(want["l2"][1], None, "LIST's L2 was never accessed")
        self.assertEqual(want["l2"][3], None, "shading has no L2")
        self.assertNumbers(fc.heights(l1), want["l1"], "L1")
        self.assertNumbers(fc.heights(l2), [v or 0 for v in want["l2"]], "L2")
        self.assertNumbers(fc.heights(dram), [100.0 * rep["stats"]["dram"]["row_hit_rate"]])
        self.assertEqual(fc.texts(ax).count("n/a"), 2)
        self.assertEqual(fc.xticks(ax), ["TRV", "LIST", "IST", "shading", "DRAM"])
        self.assertEqual(ax.get_ylabel(), "hit rate (%)")

    def test_culled_panels_are_the_bits_of_culled_npy(self):
        _, bits = self.write_run()
        fig = self.draw(run_figures.run)["culled.png"]
        panels = [ax for ax in fig.axes if ax.images]  # the others are the colour bars
        self.assertEqual(len(panels), len(bits) + 1)
        for i, b in enumerate(bits):
            np.testing.assert_array_equal(panels[i].images[0].get_array(), b)
            count = int(b.sum())
            self.assertEqual(
                panels[i].get_title(),
                f"light {i + 1}: {count:,} culled ({100 * count / b.size:.1f} %)",
            )
        np.testing.assert_array_equal(panels[-1].images[0].get_array(), bits.sum(axis=0))
        self.assertEqual(panels[-1].get_title(), f"all lights: {int(bits.sum()):,} culled")

    def test_wide_culled_panels_are_block_means(self):
        width = 1000  # over 480 pixels wide: each panel pixel is the mean of a 3x3 block
        _, bits = self.write_run(width=width, height=7, lights=2)
        panels = [ax for ax in self.draw(run_figures.run)["culled.png"].axes if ax.images]
        f = math.ceil(width / 480)
        for panel, img in zip(panels, list(bits) + [bits.sum(axis=0)]):
            want = [
                [img[y : y + f, x : x + f].mean() for x in range(0, img.shape[1], f)]
                for y in range(0, img.shape[0], f)
            ]
            np.testing.assert_allclose(panel.images[0].get_array(), want, rtol=1e-6)

    def write_sampled_run(self):
        """A sampled run: estimates with their intervals, and sample.csv's measured units."""
        rep, _ = self.write_run()
        primary, shadow = self.rng.randrange(10**5, 10**7), self.rng.randrange(10**5, 10**7)
        rep.update(sampled=True, cycles_primary=primary, cycles_shadow=shadow)
        rep["cycles_total"] = primary + shadow
        for k in ("cycles_primary", "cycles_shadow", "cycles_total"):
            rep[k + "_ci95"] = self.rng.uniform(0.001, 0.05) * rep[k]
        rep["sample"] = {"fraction": 0.05}
        self.write_json("report.json", rep)
        units = [
            {"unit": u, "first_ray": 512 * u, "weight": 20, "certain": int(u == 0)}
            for u in (0, 7, 31)
        ]
        for u in units:
            u["primary_cycles"] = self.rng.randrange(1000, 9000)
            u["shadow_cycles"] = self.rng.randrange(1000, 9000)
        self.write_csv("sample.csv", list(units[0]), units)
        return rep, units

    def test_a_sampled_run_draws_each_estimate_with_its_interval(self):
        rep, units = self.write_sampled_run()
        figures = self.draw(run_figures.run)
        fig = figures["plot_sample.png"]
        ax = fig.axes[0]
        (bar,) = [c for c in fc.bars(ax) if isinstance(c, fc.BarContainer)]
        keys = ("cycles_primary", "cycles_shadow", "cycles_total")
        self.assertNumbers(fc.heights(bar), [rep[k] for k in keys], "estimates")
        self.assertIsNotNone(bar.errorbar, "no error bars")
        # Each bar's error bar spans the estimate's 95% interval.
        lows, highs = fc.error_bars(bar.errorbar)
        self.assertNumbers(lows, [rep[k] - rep[k + "_ci95"] for k in keys], "interval lows")
        self.assertNumbers(highs, [rep[k] + rep[k + "_ci95"] for k in keys], "interval highs")
        self.assertEqual(fc.xticks(ax), ["primary", "shadow", "frame"])
        self.assertIn("sampled, 95% interval", bar.get_label())
        # The measured units, by their first rays.
        got = fc.series(fig.axes[1])
        self.assertNumbers(got["primary"][0], [u["first_ray"] for u in units])
        self.assertNumbers(got["primary"][1], [u["primary_cycles"] for u in units])
        self.assertNumbers(got["shadow"][1], [u["shadow_cycles"] for u in units])
        # Every figure's title gives the frame's estimate with its interval, and says so.
        ci = rep["cycles_total_ci95"]
        want = f"{rep['cycles_total']:,} ± {ci:,.0f} cycles"
        for name in ("plot_culling.png", "plot_time_breakdown.png", "plot_sample.png"):
            text = " ".join(fc.texts(figures[name]) + [a.get_title() for a in figures[name].axes])
            self.assertIn(want, text, name)
            self.assertIn("(sampled, 95% interval)", text, name)

    def test_a_sampled_run_without_an_interval_says_so(self):
        rep, _ = self.write_sampled_run()
        for k in ("cycles_primary", "cycles_shadow", "cycles_total"):
            rep[k + "_ci95"] = None  # too few units drawn for an interval
        self.write_json("report.json", rep)
        figures = self.draw(run_figures.run)
        title = figures["plot_culling.png"].axes[0].get_title()
        self.assertIn(f"{rep['cycles_total']:,} cycles", title)
        self.assertIn("(sampled, 95% interval unknown: too few units drawn)", title)
        self.assertIn("± ? (too few units)", fc.texts(figures["plot_sample.png"].axes[0])[0])

    def test_energy_bars_are_the_reports_parts_and_ray_types(self):
        rep, _ = self.write_run()
        self.assertNotIn("plot_energy.png", self.draw(run_figures.run))  # not priced: no figure
        rng = self.rng
        part = lambda label, static: {  # noqa: E731
            "label": label,
            "level": "L1",
            "dynamic_uj": rng.uniform(1, 100),
            **({"static_uj": rng.uniform(0, 10)} if static else {}),
        }
        units = [part("TRV", False), part("IST", False)]
        caches = [part("TRV", True), part("IST", True)]
        links = [part("TRV", False), part("L2 to memory", False)]
        types = {
            t: {"uj": rng.uniform(1, 500), "nj_per_ray": rng.uniform(1, 90)}
            for t in ("bounce", "primary", "nee")
        }
        rep["energy"] = {
            "node": "65nm",
            "total_uj": 1234.5,
            "average_power_w": 7.5,
            "units": units,
            "caches": caches,
            "links": links,
            "dram": {"dynamic_uj": 55.0, "static_uj": 800.0},
            "ray_types": types,
        }
        self.write_json("report.json", rep)
        fig = self.draw(run_figures.run)["plot_energy.png"]
        left, right = fig.axes
        bars = [b for b in left.patches]
        n = len(units) + len(caches) + 3
        dynamic = [u["dynamic_uj"] for u in units + caches]
        dynamic += [sum(link["dynamic_uj"] for link in links), 55.0, 0.0]
        static = [0.0] * len(units) + [c["static_uj"] for c in caches] + [0.0, 0.0, 800.0]
        self.assertNumbers([b.get_width() for b in bars[:n]], dynamic, "dynamic")
        self.assertNumbers([b.get_width() for b in bars[n:]], static, "static")
        self.assertEqual(
            fc.yticks(left),
            [
                "TRV ops",
                "IST ops",
                "TRV L1",
                "IST L1",
                "crossbars",
                "DRAM commands",
                "DRAM background",
            ],
        )
        self.assertEqual(fc.yticks(right), ["primary", "nee", "bounce"])  # a ray's life
        self.assertNumbers(
            [b.get_width() for b in right.patches],
            [types[t]["uj"] for t in ("primary", "nee", "bounce")],
            "ray types",
        )
        self.assertIn("1,234.5 uJ, 7.50 W", fig._suptitle.get_text())
        rep["energy"]["ray_types"]["primary"] = {"uj": "x"}
        self.write_json("report.json", rep)
        with self.assertRaises(run_figures.InputError):
            self.draw(run_figures.run)

    def test_a_full_run_has_no_sample_figure_and_no_interval(self):
        self.write_run()
        figures = self.draw(run_figures.run)
        self.assertNotIn("plot_sample.png", figures)
        for name, fig in figures.items():
            text = " ".join(fc.texts(fig) + [a.get_title() for a in fig.axes])
            self.assertNotIn("±", text, name)
            self.assertNotIn("sampled", text, name)


if __name__ == "__main__":
    fc.main()
