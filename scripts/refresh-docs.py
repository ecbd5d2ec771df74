#!/usr/bin/env python3
"""Reruns the studies behind the generated tables in docs/ and rewrites those tables (issue 19).

A generated table sits in its doc between `<!-- generated: ID -->` and
`<!-- end generated: ID -->`; study ID is configs/studies/ID.yaml. Each study runs as
`rtsim study ID --out RUNS/ID --jobs J --write-doc`: resumable, it renders the table from the
runs' own files (the report layer, C++), replaces the block, stamped with the commit of the
source tree and the date, and copies the study's figure. This script only chooses the studies and
keeps each one's runs with the commit they were made from. The prose around a table is ours: read
it again after a refresh.

  python3 scripts/refresh-docs.py --list                  the studies, their docs and costs
                                                          (rtsim study --list)
  python3 scripts/refresh-docs.py                         all of them (several hours on 2 cores)
  python3 scripts/refresh-docs.py --only cache-trv-l1,cache-ist-l1 [--runs DIR] [--jobs 2]

A study's runs are reused only if they were made from the same commit (RUNS/ID/commit.txt);
otherwise the directory is emptied and the study runs again (--reuse keeps them; the stamp then
names the binary's commit, not theirs). The binary is built first (`cmake --build build --target
rtsim`, then the programs of the build the chosen studies run) unless --no-build is given.
"""

import argparse
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def source_commit():
    """The commit of the source tree, `-dirty` when files outside docs/ differ from it (a refresh
    rewrites docs/ itself)."""

    def git(*a):
        return subprocess.run(
            ["git", "-C", ROOT, *a], check=True, capture_output=True, text=True
        ).stdout.strip()

    dirty = git("status", "--porcelain", "--untracked-files=no", "--", ".", ":(exclude)docs")
    return git("rev-parse", "--short=7", "HEAD") + ("-dirty" if dirty else "")


def study_dir(ident, args, commit):
    """The study's directory, emptied when its runs were made from another commit (kept with
    --reuse, and still marked with theirs)."""
    out = os.path.join(args.runs, ident)
    stamp = os.path.join(out, "commit.txt")
    recorded = open(stamp).read().strip() if os.path.exists(stamp) else None
    if os.path.isdir(out) and recorded != commit and not (args.reuse and recorded):
        shutil.rmtree(out)  # runs of another model: start again
    os.makedirs(out, exist_ok=True)
    if not (recorded and args.reuse):
        with open(stamp, "w") as f:
            f.write(commit + "\n")
    return out


def rtsim_studies(rtsim):
    """configs/studies/ by `rtsim study --list`: each id with the commands it runs."""
    lines = subprocess.run(
        [rtsim, "study", "--list"], check=True, capture_output=True, text=True
    ).stdout.splitlines()
    return {line.split()[0]: line for line in lines}


def build(targets):
    subprocess.run(
        ["cmake", "--build", os.path.join(ROOT, "build"), "--target", *targets], check=True
    )


def programs(studies):
    """The programs of the build the studies run (`build/NAME ...`): their targets."""
    names = [
        os.path.basename(w) for line in studies for w in line.split() if w.startswith("build/")
    ]
    return list(dict.fromkeys(names))


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
        help="keep a study's runs made from another commit (the block's stamp names this "
        "one); only where the model's cycles have not changed since",
    )
    args = ap.parse_args()
    if args.list:
        sys.exit(subprocess.run([args.rtsim, "study", "--list"]).returncode)
    if not args.no_build:
        build(["rtsim"])
    studies = rtsim_studies(args.rtsim)
    wanted = [x for x in args.only.split(",") if x] or list(studies)
    unknown = set(wanted) - set(studies)
    if unknown:
        print(
            f"refresh-docs: unknown study {', '.join(sorted(unknown))} (see --list)",
            file=sys.stderr,
        )
        sys.exit(2)
    if not args.no_build and programs(studies[x] for x in wanted):
        build(programs(studies[x] for x in wanted))
    commit = source_commit()
    for ident in wanted:
        out = study_dir(ident, args, commit)
        cmd = [args.rtsim, "study", ident, "--out", out, "--jobs", str(args.jobs), "--write-doc"]
        print("refresh-docs:", " ".join(cmd), file=sys.stderr, flush=True)
        if subprocess.run(cmd, cwd=ROOT).returncode != 0:
            raise SystemExit(f"refresh-docs: {ident} failed; its runs' logs say why")


if __name__ == "__main__":
    main()
