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
import datetime
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from docs_tables import (  # noqa: E402  (beside this script, which has no package)
    animation_hd_table,
    animation_table,
    cache_table,
    copy_markdown,
    integration_table,
    knob_table,
    SAMPLED_AREA,
    sampling_sweeps_table,
    sampling_table,
)


class Study:
    """A generated block: the runs behind it (one `rtsim` command, or several, each in its own
    sub-directory) and the function that renders the block from the run directory."""

    def __init__(
        self, ident, doc, minutes, command=None, render=None, runs=None, figure=None, jobs=None
    ):
        self.id, self.doc, self.minutes, self.render = ident, doc, minutes, render
        self.runs = runs or [("", command)]
        self.figure = figure  # (a plot of the run, its copy in docs/figures/)
        self.jobs = jobs  # runs at once, when the study times its runs (None: --jobs)

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
PAPER_RUNS = ["reproduce", "--variants", "off,paper,exact"]  # the paper's nine runs
# The paper's setups on the BVH machine (bvh-tni.yaml, bvh8), culling off and the paper's.
BVH_RUNS = ["reproduce", "--bvh", "--variants", "bvh8-off,bvh8-paper"]
# The other two BVH formats of the study (docs/bvh.md), the same way.
BVH_FORMATS = ["reproduce", "--bvh", "--variants", "bvh2-off,bvh2-paper,cwbvh8-off,cwbvh8-paper"]


# A 480x270 frame has 64 units of 2,048 rays: units of 1,024 and a tenth of them give the
# regression enough drawn units (docs/sampling.md, "Small frames").
SWEEP_SAMPLE = ["--set", "run.sample=0.1", "--set", "run.sample_unit=1024"]
SWEEP_SAMPLE += ["--set", "run.sample_strata=neyman", "--no-plots"]


def sampled(seed, strata="neyman"):
    """A sampled reproduction's options: 5% of the units, `seed`, `strata` (named even when it is
    the default, so that a block's commands say which strata ran)."""
    return [
        "--sample",
        "0.05",
        "--set",
        f"run.sample_seed={seed}",
        "--set",
        f"run.sample_strata={strata}",
    ]


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
    # Sampled frames against full ones (issue 38): the paper's nine runs in full and sampled at 5%
    # with three seeds, with strata in issue order (sK) and with Neyman's (nK, the default), one run
    # at a time so that the host times compare.
    Study(
        "sampling",
        "docs/sampling.md",
        41,
        render=sampling_table,
        runs=[("full", PAPER_RUNS)]
        + [(f"s{k}", PAPER_RUNS + sampled(k, "issue")) for k in (1, 2, 3)]
        + [(f"n{k}", PAPER_RUNS + sampled(k)) for k in (1, 2, 3)],
        jobs=1,
    ),
    # The same on the BVH machine, the default strata only.
    Study(
        "sampling-bvh",
        "docs/sampling.md",
        12,
        render=lambda run_dir: sampling_table(run_dir, "bvh"),
        runs=[("full", BVH_RUNS)] + [(f"n{k}", BVH_RUNS + sampled(k)) for k in (1, 2, 3)],
        jobs=1,
    ),
    # bvh2 and cwbvh8, two seeds.
    Study(
        "sampling-bvh-formats",
        "docs/sampling.md",
        40,
        render=lambda run_dir: sampling_table(run_dir, "bvh"),
        runs=[("full", BVH_FORMATS)] + [(f"n{k}", BVH_FORMATS + sampled(k)) for k in (1, 2)],
        jobs=1,
    ),
    # The four cache studies (480x270) in full and sampled, one seed, one run at a time.
    Study(
        "sampling-caches",
        "docs/sampling.md",
        30,
        render=sampling_sweeps_table,
        runs=[
            (f"{tag}-{name}", ["sweep", f"configs/sweeps/cache-{name}.yaml"] + options)
            for tag, options in (("full", ["--no-plots"]), ("s1", SWEEP_SAMPLE))
            for name in ("trv-l1", "ist-l1", "l2-size", "l2-banks")
        ],
        jobs=1,
    ),
    # The area-light N sweep (480x270) in full and sampled, one seed, one run at a time.
    Study(
        "sampling-area-lights",
        "docs/sampling.md",
        40,
        render=lambda run_dir: sampling_sweeps_table(run_dir, SAMPLED_AREA),
        runs=[
            (f"{tag}-area-lights", ["sweep", "configs/sweeps/area-lights.yaml"] + options)
            for tag, options in (("full", ["--no-plots"]), ("s1", SWEEP_SAMPLE))
        ],
        jobs=1,
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
        jobs = str(s.jobs or args.jobs)
        cmd = [args.rtsim] + command + ["--out", os.path.join(out, sub), "--jobs", jobs]
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
            f"took {minutes:.0f} min with --jobs {s.jobs or args.jobs}._"
        )
        replace_block(os.path.join(ROOT, s.doc), s.id, note + "\n\n" + table)
        if s.figure:
            shutil.copyfile(os.path.join(out, s.figure[0]), os.path.join(ROOT, s.figure[1]))
        print(f"refresh-docs: {s.doc}: {s.id} rewritten ({minutes:.0f} min)", file=sys.stderr)


if __name__ == "__main__":
    main()
