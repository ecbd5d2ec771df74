"""The renderers of the tables scripts/refresh-docs.py writes into docs/: each takes a study's run
directory and returns the block's Markdown."""

import csv
import json
import os
import re
from statistics import median


def fmt_int(v):
    return f"{int(round(float(v))):,}"


def fmt_pct(v):
    return f"{100 * float(v):.1f}%"


def fmt_1(v):
    return f"{float(v):.1f}"


def rows_of(run_dir):
    with open(os.path.join(run_dir, "results.csv"), newline="") as f:
        return list(csv.DictReader(f))


# The cache sweeps' columns (docs/cache-sweeps.md): every row against the Table-2 point of its
# scene in the same sweep.
CACHE_COLUMNS = [
    ("TRV L1 hits", "trv_l1_hit_rate", fmt_pct),
    ("IST L1 hits", "ist_l1_hit_rate", fmt_pct),
    ("IST L2 hits", "ist_l2_hit_rate", fmt_pct),
    ("TRV busy", "trv_busy", fmt_pct),
    ("TRV reply queue", "trv_reply_queue_cycles", fmt_1),
    ("IST reply queue", "ist_reply_queue_cycles", fmt_1),
    ("IST L2 bank stalls", "ist_l2_bank_stall_cycles", fmt_int),
    ("DRAM GB/s", "dram_bandwidth_gbps", fmt_1),
]


def cache_table(key, label, baseline):
    def render(run_dir):
        rows = rows_of(run_dir)
        base = {r["scene"]: float(r["cycles_total"]) for r in rows if r[key] == baseline}
        head = ["scene", label, "cycles", "vs Table 2"] + [c[0] for c in CACHE_COLUMNS]
        out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for r in rows:
            if r.get("failure"):
                out.append(f"| {r['scene']} | {r[key]} | failed: {r['failure']} |")
                continue
            cyc = float(r["cycles_total"])
            cells = [
                r["scene"],
                r[key],
                fmt_int(cyc),
                f"{100 * (cyc / base[r['scene']] - 1):+.1f}%",
            ]
            cells += [f(r[m]) if r[m] != "" else "-" for _, m, f in CACHE_COLUMNS]
            out.append("| " + " | ".join(cells) + " |")
        return "\n".join(out)

    return render


def knob_table(run_dir):
    """The unpublished parameters: frame ms off / on per setup and variant, change against today."""
    rows = rows_of(run_dir)
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    ms = {
        (r["scene"], r["variant"], r["run.lvb"]): float(r["frame_ms_all"])
        for r in rows
        if not r.get("failure")
    }
    head = (
        ["variant"] + [f"{s} off / on (ms)" for s in scenes] + [f"{s} off vs today" for s in scenes]
    )
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for v in variants:
        cells = [v]
        for s in scenes:
            off, on = ms.get((s, v, "false")), ms.get((s, v, "true"))
            cells.append(
                f"{off:.3f} / {on:.3f}" if off is not None and on is not None else "failed"
            )
        for s in scenes:
            off, today = ms.get((s, v, "false")), ms.get((s, "today", "false"))
            cells.append(f"{100 * (off / today - 1):+.1f}%" if off and today else "-")
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def copy_markdown(name, first_heading):
    """A report the run wrote (area_lights.md, ablation.md), from `first_heading` on, its headings
    one level down."""

    def render(run_dir):
        with open(os.path.join(run_dir, name)) as f:
            text = f.read()
        start = text.find(first_heading)
        if start < 0:
            raise SystemExit(f"refresh-docs: {name} in {run_dir} has no '{first_heading}'")
        text = text[start:].strip()
        return re.sub(r"^(#+) ", r"#\1 ", text, flags=re.M)

    return render


def animation_frames(run_dir):
    """An `rtsim animate` run's frames.csv rows, numbers as floats ('' as None), host.csv's seconds
    joined by time."""

    def floats(path):
        with open(path, newline="") as f:
            return [
                {k: float(v) if v != "" else None for k, v in r.items()} for r in csv.DictReader(f)
            ]

    host = {r["time"]: r for r in floats(os.path.join(run_dir, "host.csv"))}
    frames = floats(os.path.join(run_dir, "frames.csv"))
    for r in frames:
        r.update({k: v for k, v in host.get(r["time"], {}).items() if k != "time"})
        r["saved"] = r["cycles_off"] - r["cycles_on"]
        r["tests"] = r["lvb_region_tests"] + r["lvb_pair_tests"]
        if r["lazy_region_tests"] is not None:
            r["lazy"] = r["lazy_dirty_tests"] + r["lazy_region_tests"] + r["lazy_pair_tests"]
    return frames


ANIMATION_SCENES = ["robots", "kitchen"]


def animation_table(run_dir):
    """docs/animation.md at 480x270: per scene, medians over the frames with their range."""

    def m(v):
        return f"{v / 1e6:.2f} M"

    def ratio(a, b):
        return a / b if b else float("inf")

    def cells(fr):
        def col(k):
            return [r[k] for r in fr if r.get(k) is not None]

        saved, off, tests = col("saved"), col("cycles_off"), col("tests")
        pct = [100 * r["saved"] / r["cycles_off"] for r in fr]
        per_saved = [ratio(r["tests"], r["saved"]) for r in fr]
        lazy = [r for r in fr if r.get("lazy") is not None]
        lazy_per_saved = [ratio(r["lazy"], r["saved"]) for r in lazy]
        mlazy = median([r["lazy"] for r in lazy]) if lazy else None
        checked = col("check_mismatched_pixels")
        share = [100 * x for x in col("culled_share")]
        yield f"{fmt_int(median(off))} ({min(off) / 1e6:.2f}-{max(off) / 1e6:.2f} M)"
        yield (
            f"{fmt_int(median(saved))} ({fmt_int(min(saved))}-{fmt_int(max(saved))}), "
            f"{median(pct):.1f}% ({min(pct):.1f}-{max(pct):.1f}%)"
        )
        yield f"{median(share):.1f}% ({min(share):.1f}-{max(share):.1f}%)"
        yield " / ".join(
            m(median(col(k))) for k in ["lvb_nodes_visited", "lvb_region_tests", "lvb_pair_tests"]
        )
        yield (
            f"{median(tests) / median(saved):.1f} ({min(per_saved):.1f}-{max(per_saved):.1f})"
            if median(saved)
            else "no saving"
        )
        yield f"{median(col('kdtree_seconds')):.2f} / {median(col('lvb_seconds')):.2f}"
        if not lazy:
            yield from ["-"] * 3
        else:
            dirty = [100 * r["lazy_dirty_pairs"] / r["lazy_pairs"] for r in lazy if r["lazy_pairs"]]
            yield f"{median(dirty):.1f}% ({min(dirty):.1f}-{max(dirty):.1f}%)"
            yield (
                f"{m(mlazy)} ({100 * mlazy / median(tests):.0f}% of full; "
                f"{m(median([r['lazy_dirty_tests'] for r in lazy]))} of it finding the dirty pairs)"
            )
            yield (
                f"{mlazy / median(saved):.1f} ({min(lazy_per_saved):.1f}-{max(lazy_per_saved):.1f})"
                if median(saved)
                else "no saving"
            )
        yield f"{fmt_int(sum(checked))} in {len(checked)} frames x 2 runs"

    labels = [
        "cycles, culling off",
        "cycles culling saves",
        "shadow rays culled",
        "LVB work: nodes visited / region tests / pair tests",
        "LVB tests (region + pair) per saved cycle",
        "host seconds: kd-tree / LVB (1 thread)",
        "lazy: dirty pairs",
        "lazy: tests (dirty + region + pair)",
        "lazy tests per saved cycle",
        "`--check-every 5`: pixels differing from the reference",
    ]
    columns = [list(cells(animation_frames(os.path.join(run_dir, s)))) for s in ANIMATION_SCENES]
    out = [
        "| per frame, 480x270 | " + " | ".join(ANIMATION_SCENES) + " |",
        "|---|" + "---|" * len(columns),
    ]
    for i, label in enumerate(labels):
        out.append(f"| {label} | " + " | ".join(c[i] for c in columns) + " |")
    return "\n".join(out)


def animation_hd_table(run_dir):
    """docs/animation.md at 1920x1080: a row per frame, its saving against the same frame's at
    480x270 (the `animation` study's runs, when they are there)."""
    small_dir = os.path.join(os.path.dirname(run_dir), "animation")
    out = [
        "| frame | cycles off / on at 1920x1080 | saved | saved, x of 480x270's "
        "| LVB tests per saved cycle |",
        "|---|---|---|---|---|",
    ]
    for s in ANIMATION_SCENES:
        small = {}
        if os.path.exists(os.path.join(small_dir, s, "frames.csv")):
            small = {r["time"]: r["saved"] for r in animation_frames(os.path.join(small_dir, s))}
        for r in animation_frames(os.path.join(run_dir, s)):
            x = f"{r['saved'] / small[r['time']]:.1f}" if small.get(r["time"]) else "-"
            per = f"{r['tests'] / r['saved']:.1f}" if r["saved"] > 0 else "no saving"
            out.append(
                f"| {s} t = {r['time']:g} "
                f"| {fmt_int(r['cycles_off'])} / {fmt_int(r['cycles_on'])} | "
                f"{fmt_int(r['saved'])} ({100 * r['saved'] / r['cycles_off']:.1f}%) | {x} | {per} |"
            )
    return "\n".join(out)


def program_output(run_dir, sub):
    with open(os.path.join(run_dir, sub, "stdout.txt")) as f:
        return f.read()


def cycles_lines(text):
    """`NAME: N cycles` lines (the tests that print the figures docs quote), in order."""
    return re.findall(r"^(\S[^:\n]*): (\d+) cycles$", text, re.M)


def integration_table(run_dir):
    """docs/systemc-integration.md: the cycles the prose quotes, each with the program that
    measured it (the city at 160x90 on the paper's T&I engine unless named)."""
    out = ["| figure | cycles | measured by |", "|---|---|---|"]

    def row(figure, cycles, by):
        out.append(f"| {figure} | {cycles} | `{by}` |")

    def frames(sub):
        return ", ".join(fmt_int(c) for _, c in cycles_lines(program_output(run_dir, sub)))

    row(
        "three frames back to back on the built-in GDDR3: the setup's camera, one turned "
        "20 degrees, the setup's again",
        frames("device"),
        "build/tests/test_device --gtest_filter=Device.FramesRunBackToBack*",
    )
    row(
        "six frames on a fixed-latency memory (40 ns, no state): the same camera but the fifth "
        "(turned, its own frame buffer)",
        frames("frames"),
        "build/tests/test_frames_independent --gtest_filter=Frames.TheSameCamera*",
    )
    styles = cycles_lines(program_output(run_dir, "styles"))
    row(
        "one frame per memory target style, 40 ns, END_REQ 2 ns late where the style has one: "
        + ", ".join(name for name, _ in styles),
        ", ".join(fmt_int(c) for _, c in styles),
        "build/tests/test_tlm_target_styles",
    )
    kitchen = "../shared/scenes/bart/kitchen/kitchen.aff"
    for sub, scene in (("platform-city", "city"), ("platform-kitchen", kitchen)):
        lines = [json.loads(x) for x in program_output(run_dir, sub).splitlines() if x[:1] == "{"]
        got = [x for x in lines if "frame" in x]
        row(
            f"examples/platform, {os.path.basename(scene)} at {got[0]['pixels']:,} pixels, two "
            "cameras (interrupt "
            + ", ".join(f"{x['interrupt_ns']:,.0f}" for x in got)
            + " ns; wrong records "
            + ", ".join(str(x["wrong_records"]) for x in got)
            + ")",
            ", ".join(fmt_int(x["cycles"]) for x in got),
            f"build/platform_example {scene}",
        )
    return "\n".join(out)


# docs/sampling.md's validation (issue 38): the paper's runs in full (RUN/full) and sampled with
# several seeds (RUN/s1, RUN/s2, ...), each a `rtsim reproduce` directory with the same points.
def point_reports(sweep_dir, key="variant"):
    """A sweep's (or reproduction's) points by (scene, the value of the column `key`): each
    point's report.json. `key` may be a tuple of columns: their values joined by ", "."""
    out = {}
    points = os.path.join(sweep_dir, "points")
    for p in sorted(os.listdir(points)):
        path = os.path.join(points, p, "report.json")
        if not os.path.exists(path):
            continue
        with open(path) as f:
            r = json.load(f)
        with open(os.path.join(points, p, "row.json")) as f:
            row = json.load(f)
        keys = key if isinstance(key, tuple) else (key,)
        out[(r["scene"]["name"], ", ".join(column_value(row.get(k, "")) for k in keys))] = r
    return out


def column_value(v):
    """A sweep column's value as a table shows it: a switch (run.lvb) as on or off."""
    return ("on" if v else "off") if isinstance(v, bool) else str(v)


def sampled_cell(full, s, key):
    """The error of sampled report `s`'s `key` against the full run's, in %, and whether its 95%
    interval holds the full figure."""
    truth, est, ci = float(full[key]), float(s[key]), float(s[key + "_ci95"])
    return 100 * (est / truth - 1), 100 * ci / truth, abs(est - truth) <= ci


# The sampled runs' directories by plan: sK (run.sample_strata: issue), nK (neyman, the default);
# K the seed.
SAMPLING_PLANS = [
    ("s", "Strata in issue order (`run.sample_strata: issue`)"),
    ("n", "Neyman's strata on the walk steps (`run.sample_strata: neyman`, the default)"),
]


def sampling_table(run_dir, sub=""):
    """The sampled runs against the full ones; `sub`: where in each run's directory its points
    are (`bvh` for `rtsim reproduce --bvh`)."""
    full = point_reports(os.path.join(run_dir, "full", sub))
    out = []
    for prefix, title in SAMPLING_PLANS:
        seeds = sorted(d for d in os.listdir(run_dir) if re.fullmatch(prefix + r"\d+", d))
        if seeds:
            out += ["" if out else None, f"{title}:", ""]
            out += sampling_plan_rows(run_dir, full, seeds, sub)
    return "\n".join(x for x in out if x is not None) + "\n"


def off_variant(variant):
    """The variant with culling off that `variant` is compared with: `off`, or `bvh8-off` for
    `bvh8-paper`."""
    return variant[: variant.rfind("-") + 1] + "off"


class SampledTally:
    """Sampled runs against their full ones, row by row: each seed's error and interval, and over
    every row the errors, the intervals that missed and the speedups."""

    def __init__(self):
        self.errors, self.missed, self.speedups = [], [], []
        self.held = {"total": 0, "primary": 0, "shadow": 0}

    def cells(self, name, full, runs):
        """The cells of row `name` (full report `full`; `runs`: (seed, its report or None)): one
        per seed, then the median speedup."""
        cells, ups = [], []
        for seed, r in runs:
            if r is None:
                cells.append("-")
                continue
            err, ci, ok = sampled_cell(full, r, "cycles_total")
            self.errors.append(abs(err))
            for phase in self.held:
                self.held[phase] += sampled_cell(full, r, f"cycles_{phase}")[2]
            if not ok:
                self.missed.append(f"{name}, seed {seed}")
            cells.append(f"{err:+.2f}% / {ci:.2f}%" + ("" if ok else " (missed)"))
            ups.append(full["host"]["seconds"]["total"] / r["host"]["seconds"]["total"])
        self.speedups += ups
        return cells + [f"{median(ups):.1f}x" if ups else "-"]

    def summary(self, what):
        n, e, held, ups = len(self.errors), self.errors, self.held, self.speedups
        return (
            f"{n} sampled {what}: the largest error {max(e):.2f}%, "
            f"{sum(x <= 2 for x in e)} of {n} within 2%; the 95% interval held the full run's "
            f"frame in {held['total']} of {n}"
            + (f" (missed: {'; '.join(self.missed)})" if self.missed else "")
            + f", its primary phase in {held['primary']}, its shadow phase in {held['shadow']}; "
            f"host time {median(ups):.1f}x less (median; from {min(ups):.1f}x to {max(ups):.1f}x)."
        )


def sampling_plan_rows(run_dir, full, seeds, sub=""):
    sampled = {s: point_reports(os.path.join(run_dir, s, sub)) for s in seeds}
    head = ["setup", "full run (cycles)"] + [f"seed {s[1:]}: error / interval" for s in seeds]
    head += ["speedup (median)"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    tally = SampledTally()
    for key, f in full.items():
        name = f"{key[0]}, {key[1]}"
        cells = tally.cells(name, f, [(s[1:], sampled[s].get(key)) for s in seeds])
        out.append("| " + " | ".join([name, fmt_int(f["cycles_total"])] + cells) + " |")
    out += ["", tally.summary("frames")]
    out += [
        "",
        "Culling's frame-time reduction (1 - on / off), full run and each seed's error in "
        "points:",
        "",
        "| setup | full run | " + " | ".join(f"seed {s[1:]}" for s in seeds) + " |",
        "|" + "---|" * (2 + len(seeds)),
    ]
    for (scene, variant), f in full.items():
        off = full.get((scene, off_variant(variant)))
        if variant == off_variant(variant) or off is None:
            continue
        red = 100 * (1 - f["cycles_total"] / off["cycles_total"])
        cells = [f"{scene}, {variant}", f"{red:.2f}%"]
        for s in seeds:
            on_s = sampled[s].get((scene, variant))
            off_s = sampled[s].get((scene, off_variant(variant)))
            if on_s is None or off_s is None:
                cells.append("-")
                continue
            r = 100 * (1 - on_s["cycles_total"] / off_s["cycles_total"])
            cells.append(f"{r - red:+.2f} pt")
        out.append("| " + " | ".join(cells) + " |")
    return out


# The cache sweeps sampled beside their full runs (docs/sampling.md): each sweep's directory
# full-NAME and sK-NAME (seed K), the column (or columns) that tell its points apart.
SAMPLED_SWEEPS = [
    ("trv-l1", "hw.trv.l1.size_kb", "TRV L1 KB"),
    ("ist-l1", "hw.ist.l1.size_kb", "IST L1 KB"),
    ("l2-size", "variant", "L2"),
    ("l2-banks", "variant", "L2 banks"),
]
# The area-light N sweep (configs/sweeps/area-lights.yaml): samples per light, and culling.
SAMPLED_AREA = [
    ("area-lights", ("scene.lights.area_from_points.samples", "run.lvb"), "N, culling"),
]


def sampling_sweeps_table(run_dir, sweeps=None):
    """Each sampled sweep point against the full one: error and 95% interval, whether the
    interval held, the host-time speedup; a summary line over every point."""
    seeds = sorted({d.split("-")[0] for d in os.listdir(run_dir) if re.fullmatch(r"s\d+-.+", d)})
    head = ["sweep", "scene", "point", "full run (cycles)"]
    head += [f"seed {s[1:]}: error / interval" for s in seeds] + ["speedup"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    tally = SampledTally()
    for name, key, label in sweeps or SAMPLED_SWEEPS:
        full = point_reports(os.path.join(run_dir, f"full-{name}"), key)
        sampled = {s: point_reports(os.path.join(run_dir, f"{s}-{name}"), key) for s in seeds}
        for (scene, value), f in full.items():
            runs = [(s[1:], sampled[s].get((scene, value))) for s in seeds]
            cells = tally.cells(f"{name}, {scene}, {value}", f, runs)
            row = [name, scene, f"{label} {value}", fmt_int(f["cycles_total"])] + cells
            out.append("| " + " | ".join(row) + " |")
    return "\n".join(out + ["", tally.summary("points")]) + "\n"
