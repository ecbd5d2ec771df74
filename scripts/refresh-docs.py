#!/usr/bin/env python3
"""Reruns the studies behind the generated tables in docs/ and rewrites those tables (issue 19).

A generated table sits in its doc between `<!-- generated: ID -->` and
`<!-- end generated: ID -->`; study ID is configs/studies/ID.yaml. This script reruns it
(resumable, in RUNS/ID), renders the table from the run's own files and replaces the block, stamped
with the commit of the source tree the binary was built from and the date. A study whose table the
report layer renders runs as `rtsim study ID --write-doc` (it writes the block and copies the
figure); the others (`rtsim study --list` marks them "table: Python") still run and render here,
from the STUDIES below, until their renderers are ported. The prose around a table is ours: read it
again after a refresh.

  python3 scripts/refresh-docs.py --list                  the studies, their docs and costs
                                                          (rtsim study --list)
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
    integration_table,
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


SMALL = ["--width", "480", "--height", "270", "--check-every", "5"]


# The studies whose tables are still rendered here (scripts/docs_tables.py); each is also
# configs/studies/ID.yaml, which `rtsim study` runs once its renderer is ported.
STUDIES = [
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


def study_dir(ident, args, commit):
    """The study's directory, emptied when its runs were made from another commit (kept with
    --reuse); returns it and the commit its points were run from."""
    out = os.path.join(args.runs, ident)
    stamp = os.path.join(out, "commit.txt")
    recorded = open(stamp).read().strip() if os.path.exists(stamp) else None
    if os.path.isdir(out) and recorded != commit and not (args.reuse and recorded):
        shutil.rmtree(out)  # runs of another model: start again
    if recorded and args.reuse:
        commit = recorded  # the points' own commit; new points come from this binary's
    os.makedirs(out, exist_ok=True)
    with open(stamp, "w") as f:
        f.write(commit + "\n")
    return out, commit


def run_study(s, args, commit):
    """Runs (or resumes) the study; returns its directory, the minutes it took and the commit its
    points were run from."""
    out, commit = study_dir(s.id, args, commit)
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


def render_here(s, args, commit):
    """A study whose table is still rendered here: its runs, its table, its block and figure."""
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


def rtsim_studies(rtsim):
    """configs/studies/ by `rtsim study --list`: every id, and those whose tables it renders (it
    marks the others "(table: Python)")."""
    lines = subprocess.run(
        [rtsim, "study", "--list"], check=True, capture_output=True, text=True
    ).stdout.splitlines()
    every = [line.split()[0] for line in lines]
    ported = [line.split()[0] for line in lines if not line.endswith("(table: Python)")]
    return every, ported


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
        sys.exit(subprocess.run([args.rtsim, "study", "--list"]).returncode)
    if not args.no_build:
        subprocess.run(
            ["cmake", "--build", os.path.join(ROOT, "build"), "--target", "rtsim"], check=True
        )
    every, ported = rtsim_studies(args.rtsim)
    wanted = [x for x in args.only.split(",") if x] or every
    unknown = set(wanted) - set(every)
    if unknown:
        print(
            f"refresh-docs: unknown study {', '.join(sorted(unknown))} (see --list)",
            file=sys.stderr,
        )
        sys.exit(2)
    commit = source_commit()
    for ident in (x for x in ported if x in wanted):
        out, _ = study_dir(ident, args, commit)
        cmd = [args.rtsim, "study", ident, "--out", out, "--jobs", str(args.jobs), "--write-doc"]
        print("refresh-docs:", " ".join(cmd), file=sys.stderr, flush=True)
        if subprocess.run(cmd, cwd=ROOT).returncode != 0:
            raise SystemExit(f"refresh-docs: {ident} failed; its points' log.txt say why")
    for s in STUDIES:
        if s.id in wanted and s.id not in ported:
            render_here(s, args, commit)


if __name__ == "__main__":
    main()
