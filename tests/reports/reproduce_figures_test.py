#!/usr/bin/env python3
"""The paper-vs-ours figures (plots.py reproduce, reports/rtsim_plots/reproduce_figures.py) show
the numbers of reproduction.json: per scene panel, each source's bars (found by the colour the
legend gives it) are compared with the percentages the test computes from the file it wrote.
Usage: reproduce_figures_test.py SOURCE_DIR"""

import random

import figure_check as fc

reproduce_figures = fc.module("reproduce_figures")
# The legend's label of each source in reproduction.json.
PAPER = "paper (published)"
OURS = {
    "paper": "ours, paper's method",
    "paper-contained": "ours, paper's method, contained",
    "exact": "ours, exact mode",
}


def ours(rng, lights, no_rays=()):
    shadow = [0 if i in no_rays else rng.randrange(1000, 10**5) for i in range(lights)]
    nonempty = [rng.randrange(1000, 10**4) for _ in range(lights)]
    return {
        "frame_ms_all": rng.uniform(1, 2),
        "frame_ms_shadow": rng.uniform(0.2, 1),
        "culled_rays": [rng.randrange(0, s + 1) for s in shadow],
        "shadow_rays": shadow,
        "culled_leaves": [rng.randrange(0, n) for n in nonempty],
        "nonempty_leaves": nonempty,
        "leaves": 2 * max(nonempty),
        "pixels_shadow_differs_from_off": rng.randrange(0, 100),
    }


def off_run(rng):
    """Culling off: slower than any run with culling (ours())."""
    return {"frame_ms_all": rng.uniform(2, 3), "frame_ms_shadow": rng.uniform(1, 2)}


def reproduction(rng):
    """reproduction.json as `rtsim reproduce` writes it: robots with the paper's figures for 3
    lights and our runs with 4, but no paper-contained run; bunny without the paper's figures, and
    a light of our exact run without shadow rays."""
    paper = {
        "culled_leaves": [rng.randrange(0, 30000) for _ in range(3)],
        "leaves": 34509,
        "culled_rays": [rng.randrange(0, 10**5) for _ in range(3)],
        "shadow_rays_per_light": 10**5,
        "ms": {k: rng.uniform(1, 5) for k in ("all_on", "all_off", "shadow_on", "shadow_off")},
    }
    robots = {"paper": ours(rng, 4), "exact": ours(rng, 4), "off": off_run(rng)}
    bunny = {"paper": ours(rng, 2), "exact": ours(rng, 2, no_rays=[1]), "off": off_run(rng)}
    return {
        "schema": "rtsim-reproduction/1",
        "scenes": [
            {"name": "robots", "title": "Robots", "paper": paper, "ours": robots},
            {"name": "bunny", "title": "Bunny", "ours": bunny},
        ],
    }


def pct(part, whole):
    return 100.0 * part / whole if whole else None


def culled(scene, kind):
    """label -> per-light % culled (None where there is no denominator) of each source present."""
    out = {}
    p = scene.get("paper")
    if p:
        whole = p["shadow_rays_per_light"] if kind == "rays" else p["leaves"]
        out[PAPER] = [
            pct(c, whole) for c in p["culled_rays" if kind == "rays" else "culled_leaves"]
        ]
    for var, label in OURS.items():
        o = scene["ours"].get(var)
        if o:
            parts, wholes = (
                ("culled_rays", "shadow_rays")
                if kind == "rays"
                else ("culled_leaves", "nonempty_leaves")
            )
            out[label] = [pct(c, w) for c, w in zip(o[parts], o[wholes])]
    return out


def reductions(scene):
    """label -> [all rays, shadow rays] frame-time reduction (%) of each source present."""
    out = {}
    if scene.get("paper"):
        ms = scene["paper"]["ms"]
        out[PAPER] = [
            100 * (ms[f"{k}_off"] - ms[f"{k}_on"]) / ms[f"{k}_off"] for k in ("all", "shadow")
        ]
    off = scene["ours"]["off"]
    for var, label in OURS.items():
        on = scene["ours"].get(var)
        if on:
            out[label] = [
                100 * (off[f"frame_ms_{k}"] - on[f"frame_ms_{k}"]) / off[f"frame_ms_{k}"]
                for k in ("all", "shadow")
            ]
    return out


class ReproduceFigures(fc.FigureTest):
    def setUp(self):
        super().setUp()
        self.rep = reproduction(random.Random(46))
        self.write_json("reproduction.json", self.rep)
        self.figures = self.draw(reproduce_figures.reproduce)

    def bars_by_source(self, ax, colours):
        """legend label -> bar heights of the source drawn in that colour."""
        out = {}
        for container in (c for c in fc.bars(ax) if isinstance(c, fc.BarContainer)):
            colour = tuple(container.patches[0].get_facecolor())
            [label] = [k for k, c in colours.items() if c == colour]
            out[label] = fc.heights(container)
        return out

    def expect_bars(self, ax, colours, want, lights, what):
        got = self.bars_by_source(ax, colours)
        self.assertEqual(sorted(got), sorted(want), f"{what}: the sources drawn")
        for label, values in want.items():
            values = values + [None] * (lights - len(values))  # n/a past a source's own lights
            self.assertNumbers(got[label], [v or 0 for v in values], f"{what}, {label}")
        nones = sum(v is None for values in want.values() for v in values)
        nones += sum(lights - len(values) for values in want.values())
        self.assertEqual(fc.texts(ax).count("n/a"), nones, f"{what}: n/a labels")

    def test_culling_panels_show_each_source_s_culled_share_per_light(self):
        fig = self.figures["reproduce_culling.png"]
        top, rays_fig, leaves_fig = fig.subfigs
        colours = fc.legend(top)
        self.assertEqual(sorted(colours), sorted([PAPER] + list(OURS.values())))
        for sub, kind, ylabel in (
            (rays_fig, "rays", "shadow rays"),
            (leaves_fig, "leaves", "leaves"),
        ):
            panels = sub.axes
            self.assertEqual(len(panels), 2, "a panel per scene")
            for ax, scene in zip(panels, self.rep["scenes"]):
                lights = max(len(v) for v in culled(scene, kind).values())
                what = f"{scene['name']} {kind}"
                self.expect_bars(ax, colours, culled(scene, kind), lights, what)
                self.assertEqual(fc.xticks(ax), [f"L{i + 1}" for i in range(lights)])
                self.assertTrue(ax.get_title().startswith(scene["title"]), ax.get_title())
            self.assertEqual(panels[0].get_ylabel(), f"{ylabel} culled (%)")
        self.assertIn("missing: the paper's figures", panels[1].get_title())

    def test_time_panels_show_each_source_s_frame_time_reduction(self):
        fig = self.figures["reproduce_time.png"]
        top, main = fig.subfigs
        colours = fc.legend(top)
        for ax, scene in zip(main.axes, self.rep["scenes"]):
            want = reductions(scene)
            got = self.bars_by_source(ax, colours)
            for label in colours:  # every source has its slot; a missing one shows n/a
                self.assertNumbers(got[label], want.get(label, [0, 0]), f"{scene['name']}, {label}")
            self.assertEqual(fc.texts(ax).count("n/a"), 2 * (len(colours) - len(want)))
            self.assertEqual(fc.xticks(ax), ["all rays", "shadow rays"])
            self.assertTrue(ax.get_title().startswith(scene["title"]), ax.get_title())
        self.assertEqual(main.axes[0].get_ylabel(), "frame-time reduction (%)")

    def test_sampled_runs_draw_each_reduction_with_its_interval(self):
        for scene in self.rep["scenes"]:
            for var, run in scene["ours"].items():
                run["frame_ms_all_ci95"], run["frame_ms_shadow_ci95"] = 0.01, 0.02
                if var != "off":  # as reproduction.json gives them: in points of %
                    run["reduction"] = {
                        k: {"reduction_pct": 0, "ci95_pt": ci, "paired": True}
                        for k, ci in (("all", 0.5), ("shadow", 1.5))
                    }
        self.write_json("reproduction.json", self.rep)
        fig = self.draw(reproduce_figures.reproduce)["reproduce_time.png"]
        self.assertIn("error bars on ours: sampled, 95% interval", " ".join(fc.texts(fig)))
        top, main = fig.subfigs
        colours = fc.legend(top)
        for ax, scene in zip(main.axes, self.rep["scenes"]):
            want = reductions(scene)
            drawn = 0
            for bar in (c for c in fc.bars(ax) if isinstance(c, fc.BarContainer)):
                [label] = [
                    k for k, c in colours.items() if c == tuple(bar.patches[0].get_facecolor())
                ]
                if label == PAPER or label not in want:  # exact, or not run: no error bar
                    self.assertIsNone(bar.errorbar, label)
                    continue
                lows, highs = fc.error_bars(bar.errorbar)
                self.assertNumbers(lows, [want[label][0] - 0.5, want[label][1] - 1.5], label)
                self.assertNumbers(highs, [want[label][0] + 0.5, want[label][1] + 1.5], label)
                drawn += 1
            self.assertEqual(drawn, len(scene["ours"]) - 1, scene["name"])
            self.assertIn(" ± 0.010 → ", ax.get_xlabel())  # the times with theirs


if __name__ == "__main__":
    fc.main()
