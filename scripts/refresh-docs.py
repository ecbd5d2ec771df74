#!/usr/bin/env python3
"""Reruns the studies behind the generated tables in docs/ and rewrites those tables (issue 19).

A generated table sits in its doc between `<!-- generated: ID -->` and
`<!-- end generated: ID -->`; this script reruns study ID (a sweep or `rtsim reproduce --ablation`,
resumable, in RUNS/ID), renders the table from the run's own files and replaces the block, stamped
with the commit of the source tree the binary was built from and the date. The prose around a
table is ours: read it again after a refresh.

  python3 scripts/refresh-docs.py --list                  the studies, their docs and costs
  python3 scripts/refresh-docs.py                         all of them (several hours on 2 cores)
  python3 scripts/refresh-docs.py --only cache-trv-l1,cache-ist-l1 [--runs DIR] [--jobs 2]

A study's runs are reused only if they were made from the same commit (RUNS/ID/commit.txt);
otherwise the directory is emptied and the study runs again (--reuse keeps them, and the stamp
names their commit). The binary is built first
(`cmake --build build --target rtsim`) unless --no-build is given.
"""

import argparse
import csv
import datetime
import os
import re
import shutil
import subprocess
import sys
from statistics import median

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


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
    ("TRV reply queue", "stats.trv.icnt.reply.avg_queue_cycles", fmt_1),
    ("IST reply queue", "stats.ist.icnt.reply.avg_queue_cycles", fmt_1),
    ("IST L2 bank stalls", "stats.ist.l2.bank.stall_cycles", fmt_int),
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
    import json

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


class Study:
    """A generated block: the runs behind it (one `rtsim` command, or several, each in its own
    sub-directory) and the function that renders the block from the run directory."""

    def __init__(self, ident, doc, minutes, command=None, render=None, runs=None, figure=None):
        self.id, self.doc, self.minutes, self.render = ident, doc, minutes, render
        self.runs = runs or [("", command)]
        self.figure = figure  # (a plot of the run, its copy in docs/figures/)

    def describe(self):
        return "; ".join(
            " ".join(c) if c[0].startswith("build/") else "rtsim " + " ".join(c)
            for _, c in self.runs
        )


def animate(scene, times, *options):
    return (
        scene,
        [
            "animate",
            f"configs/scenes/{scene}.yaml",
            "--hw",
            "configs/hw/tni-paper.yaml",
            "--times",
            times,
            *options,
            "--lvb",
            "both",
        ],
    )


def cache_study(name, minutes, key, label, baseline):
    """docs/cache-sweeps.md: configs/sweeps/cache-NAME.yaml, its table and its cycles plot."""
    return Study(
        f"cache-{name}",
        "docs/cache-sweeps.md",
        minutes,
        ["sweep", f"configs/sweeps/cache-{name}.yaml"],
        cache_table(key, label, baseline),
        figure=(f"plots/cycles_total_vs_{key}.png", f"docs/figures/sweep-{name}.png"),
    )


SMALL = ["--width", "480", "--height", "270", "--check-every", "5"]
STUDIES = [
    cache_study("trv-l1", 3, "hw.trv.l1.size_kb", "TRV L1 KB", "8"),
    cache_study("ist-l1", 3, "hw.ist.l1.size_kb", "IST L1 KB", "16"),
    cache_study("l2-size", 5, "variant", "L2", "table2-128k"),
    cache_study("l2-banks", 5, "variant", "L2 banks", "banks-8"),
    Study(
        "unpublished-knobs",
        "docs/ablation.md",
        35,
        ["sweep", "configs/sweeps/unpublished-knobs.yaml", "--no-plots"],
        knob_table,
    ),
    Study(
        "unpublished-knobs-hd",
        "docs/ablation.md",
        45,
        ["sweep", "configs/sweeps/unpublished-knobs-hd.yaml", "--no-plots"],
        knob_table,
    ),
    # The area-light sweeps write area_lights.md (reports/area_report.cpp) and, with plots.py, the
    # figure.
    Study(
        "area-lights",
        "docs/area-lights.md",
        30,
        ["sweep", "configs/sweeps/area-lights.yaml"],
        copy_markdown("area_lights.md", "| scene"),
        figure=("plots/area_reduction.png", "docs/figures/area-reduction.png"),
    ),
    Study(
        "area-lights-hd",
        "docs/area-lights.md",
        70,
        ["sweep", "configs/sweeps/area-lights-hd.yaml"],
        copy_markdown("area_lights.md", "| scene"),
    ),
    Study(
        "ablation",
        "docs/ablation.md",
        65,
        ["reproduce", "--ablation"],
        copy_markdown("ablation.md", "Sweep `ablation.yaml`"),
    ),
    Study(
        "bvh",
        "docs/bvh.md",
        45,
        ["reproduce", "--bvh"],
        copy_markdown("bvh.md", "Sweep `bvh-study.yaml`"),
    ),
    # The integration doc's figures: examples and tests that print them (no rtsim run).
    Study(
        "integration",
        "docs/systemc-integration.md",
        2,
        render=integration_table,
        runs=[
            ("device", ["build/tests/test_device", "--gtest_filter=Device.FramesRunBackToBack*"]),
            (
                "frames",
                ["build/tests/test_frames_independent", "--gtest_filter=Frames.TheSameCamera*"],
            ),
            ("styles", ["build/tests/test_tlm_target_styles"]),
            ("platform-city", ["build/platform_example", "city"]),
            (
                "platform-kitchen",
                ["build/platform_example", "../shared/scenes/bart/kitchen/kitchen.aff"],
            ),
        ],
    ),
    Study(
        "animation",
        "docs/animation.md",
        12,
        render=animation_table,
        runs=[animate("robots", "0:10:0.5", *SMALL), animate("kitchen", "0:20:1", *SMALL)],
    ),
    Study(
        "animation-hd",
        "docs/animation.md",
        26,
        render=animation_hd_table,
        runs=[animate("robots", "0:10:5"), animate("kitchen", "0:20:10")],
    ),
]


def source_commit():
    """The commit of the source tree, `-dirty` when files outside docs/ differ from it (a refresh
    rewrites docs/ itself)."""

    def git(*a):
        return subprocess.run(
            ["git", "-C", ROOT, *a], check=True, capture_output=True, text=True
        ).stdout.strip()

    dirty = git("status", "--porcelain", "--untracked-files=no", "--", ".", ":(exclude)docs")
    return git("rev-parse", "--short=7", "HEAD") + ("-dirty" if dirty else "")


def replace_block(doc_path, ident, body):
    with open(doc_path) as f:
        text = f.read()
    begin, end = f"<!-- generated: {ident} -->", f"<!-- end generated: {ident} -->"
    i, j = text.find(begin), text.find(end)
    if i < 0 or j < i:
        raise SystemExit(f"refresh-docs: {doc_path} has no block '{begin}' ... '{end}'")
    text = text[: i + len(begin)] + "\n" + body.strip() + "\n" + text[j:]
    tmp = doc_path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, doc_path)


def run_program(out, sub, command):
    """A program of the build run from the source tree; its output kept in OUT/SUB/stdout.txt
    (a skipped test, exit 77 or GTEST_SKIP, leaves `skipped` there)."""
    os.makedirs(os.path.join(out, sub), exist_ok=True)
    path = os.path.join(out, sub, "stdout.txt")
    if os.path.exists(path):  # resumed
        return
    cmd = [os.path.join(ROOT, command[0])] + command[1:]
    print("refresh-docs:", " ".join(cmd), file=sys.stderr, flush=True)
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(
            f"refresh-docs: {' '.join(command)} failed (exit {r.returncode}):\n{r.stderr}"
        )
    with open(path + ".tmp", "w") as f:
        f.write(r.stdout)
    os.replace(path + ".tmp", path)


def run_study(s, args, commit):
    """Runs (or resumes) the study; returns its directory, the minutes it took and the commit its
    points were run from."""
    out = os.path.join(args.runs, s.id)
    stamp = os.path.join(out, "commit.txt")
    recorded = open(stamp).read().strip() if os.path.exists(stamp) else None
    if os.path.isdir(out) and recorded != commit and not (args.reuse and recorded):
        shutil.rmtree(out)  # runs of another model: start again
    if recorded and args.reuse:
        commit = recorded  # the points' own commit; new points come from this binary's
    os.makedirs(out, exist_ok=True)
    with open(stamp, "w") as f:
        f.write(commit + "\n")
    start = datetime.datetime.now()
    for sub, command in s.runs:
        if command[0].startswith("build/"):  # a program of the build (an example, a test)
            run_program(out, sub, command)
            continue
        # Absolute paths: a sweep's manifest names its inputs as resolved from them.
        command = [os.path.join(ROOT, a) if a.endswith(".yaml") else a for a in command]
        cmd = [args.rtsim] + command + ["--out", os.path.join(out, sub), "--jobs", str(args.jobs)]
        print("refresh-docs:", " ".join(cmd), file=sys.stderr, flush=True)
        code = subprocess.run(cmd, cwd=ROOT).returncode
        if code != 0:
            raise SystemExit(
                f"refresh-docs: {s.id} failed (exit {code}); its points' log.txt say why"
            )
    minutes = (datetime.datetime.now() - start).total_seconds() / 60
    return out, minutes, commit


def main():
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--rtsim", default=os.path.join(ROOT, "build", "rtsim"))
    ap.add_argument("--runs", default=os.path.join(ROOT, "out", "refresh-docs"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default="", help="comma-separated study ids (default: all)")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--no-build", action="store_true")
    ap.add_argument(
        "--reuse",
        action="store_true",
        help="keep a study's runs made from another commit (stamped with that commit); "
        "only where the model's cycles have not changed since",
    )
    args = ap.parse_args()
    if args.list:
        for s in STUDIES:
            print(f"{s.id:20} {s.doc:22} ~{s.minutes} min   {s.describe()}")
        return
    wanted = [x for x in args.only.split(",") if x] or [s.id for s in STUDIES]
    unknown = set(wanted) - {s.id for s in STUDIES}
    if unknown:
        print(
            f"refresh-docs: unknown study {', '.join(sorted(unknown))} (see --list)",
            file=sys.stderr,
        )
        sys.exit(2)
    if not args.no_build:
        subprocess.run(
            ["cmake", "--build", os.path.join(ROOT, "build"), "--target", "rtsim"], check=True
        )
    commit = source_commit()
    for s in STUDIES:
        if s.id not in wanted:
            continue
        out, minutes, ran_at = run_study(s, args, commit)
        table = s.render(out)
        note = (
            f"_Generated by `python3 scripts/refresh-docs.py --only {s.id}` (`{s.describe()}`) "
            f"from commit {ran_at} on {datetime.date.today()}; this sitting "
            f"took {minutes:.0f} min with --jobs {args.jobs}._"
        )
        replace_block(os.path.join(ROOT, s.doc), s.id, note + "\n\n" + table)
        if s.figure:
            shutil.copyfile(os.path.join(out, s.figure[0]), os.path.join(ROOT, s.figure[1]))
        print(f"refresh-docs: {s.doc}: {s.id} rewritten ({minutes:.0f} min)", file=sys.stderr)


if __name__ == "__main__":
    main()
