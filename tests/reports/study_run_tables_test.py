#!/usr/bin/env python3
"""The tables `rtsim study` renders from animations and from what programs of the build print
(reports/study_animation_tables.h, study_integration_table.h), worked out by hand on run
directories built here: the medians and ranges of an animation's frames, the per-frame table
against the smaller study beside it (and without it), the integration table's rows in the study
file's order with its texts and commands; a run that lacks a file is one error naming it.

Usage: study_run_tables_test.py SOURCE_DIR RTSIM_BINARY"""

import os
import shutil
import sys
import tempfile

import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from study_check import check, finish, render, render_error  # noqa: E402  (no package)

src, rtsim = sys.argv[1], sys.argv[2]
KEYS = [
    "time",
    "cycles_off",
    "cycles_on",
    "culled_share",
    "lvb_nodes_visited",
    "lvb_region_tests",
    "lvb_pair_tests",
    "lazy_dirty_pairs",
    "lazy_pairs",
    "lazy_dirty_tests",
    "lazy_region_tests",
    "lazy_pair_tests",
    "check_mismatched_pixels",
]


def frames(run_dir, rows):
    """An `rtsim animate` directory's frames.csv (KEYS) and host.csv."""
    os.makedirs(run_dir)
    with open(os.path.join(run_dir, "frames.csv"), "w") as f:
        f.write(",".join(KEYS) + "\n" + "".join(",".join(map(str, r)) + "\n" for r in rows))
    with open(os.path.join(run_dir, "host.csv"), "w") as f:
        f.write("time,kdtree_seconds,lvb_seconds,simulate_seconds_off,simulate_seconds_on\n")
        f.write("".join(f"{r[0]},0.25,0.5,1,1\n" for r in rows))


def table(head, rows):
    """A Markdown table as the renderers write it."""
    lines = [head, None] + rows
    return "".join(
        "|" + "---|" * len(head) + "\n" if r is None else "| " + " | ".join(r) + " |\n"
        for r in lines
    )


def same(study, got, want):
    check(got == want, f"{study}: got\n{got}\nexpected\n{want}")


# An animation: robots with a lazy rebuild in two of its frames, the kitchen without one and
# with a frame culling saves nothing in.
with tempfile.TemporaryDirectory() as tmp:
    small = os.path.join(tmp, "animation")
    frames(
        os.path.join(small, "robots"),
        [
            (0, 1000, 900, 0.1, 10, 200, 0, "", "", "", "", "", 0),
            (1, 2000, 1900, 0.3, 20, 400, 100, 5, 20, 30, 20, 10, ""),
            (2, 4000, 3600, 0.2, 30, 300, 200, 10, 20, 50, 10, 20, 3),
        ],
    )
    frames(
        os.path.join(small, "kitchen"),
        [
            (0, 1000, 1000, 0.1, 1e6, 2e6, 1e6, "", "", "", "", "", 1),
            (1, 3e6, 2e6, 0.2, 3e6, 4e6, 2e6, "", "", "", "", "", ""),
        ],
    )
    # Saved: robots 100, 100, 400 (10%, 5%, 10%), kitchen 0 and 1e6 (0%, 33.3%); LVB tests
    # (region + pair) 200, 500, 500 and 3e6, 6e6; lazy tests 60 and 80 (14% of 500).
    same(
        "animation",
        render(rtsim, "animation", small),
        table(
            ["per frame, 480x270", "robots", "kitchen"],
            [
                ["cycles, culling off", "2,000 (0.00-0.00 M)", "1,500,500 (0.00-3.00 M)"],
                [
                    "cycles culling saves",
                    "100 (100-400), 10.0% (5.0-10.0%)",
                    "500,000 (0-1,000,000), 16.7% (0.0-33.3%)",
                ],
                ["shadow rays culled", "20.0% (10.0-30.0%)", "15.0% (10.0-20.0%)"],
                [
                    "LVB work: nodes visited / region tests / pair tests",
                    "0.00 M / 0.00 M / 0.00 M",
                    "2.00 M / 3.00 M / 1.50 M",
                ],
                ["LVB tests (region + pair) per saved cycle", "5.0 (1.2-5.0)", "9.0 (6.0-inf)"],
                ["host seconds: kd-tree / LVB (1 thread)", "0.25 / 0.50", "0.25 / 0.50"],
                ["lazy: dirty pairs", "37.5% (25.0-50.0%)", "-"],
                [
                    "lazy: tests (dirty + region + pair)",
                    "0.00 M (14% of full; 0.00 M of it finding the dirty pairs)",
                    "-",
                ],
                ["lazy tests per saved cycle", "0.7 (0.2-0.6)", "-"],
                [
                    "`--check-every 5`: pixels differing from the reference",
                    "3 in 2 frames x 2 runs",
                    "1 in 1 frames x 2 runs",
                ],
            ],
        ),
    )
    hd = os.path.join(tmp, "animation-hd")
    frames(os.path.join(hd, "robots"), [(1, 20000, 18000, 0.3, 20, 400, 400, *[""] * 6)])
    frames(os.path.join(hd, "kitchen"), [(5, 1000, 1100, 0.3, 20, 400, 400, *[""] * 6)])
    head = (
        "| frame | cycles off / on at 1920x1080 | saved | saved, x of 480x270's "
        "| LVB tests per saved cycle |\n|---|---|---|---|---|\n"
    )
    # robots t = 1 saved 2,000 against 100 at 480x270, 800 tests; kitchen t = 5 has no
    # 480x270 frame, and loses.
    same(
        "animation-hd",
        render(rtsim, "animation-hd", hd),
        head + "| robots t = 1 | 20,000 / 18,000 | 2,000 (10.0%) | 20.0 | 0.4 |\n"
        "| kitchen t = 5 | 1,000 / 1,100 | -100 (-10.0%) | - | no saving |\n",
    )
    shutil.rmtree(small)
    same(
        "animation-hd without the 480x270 study",
        render(rtsim, "animation-hd", hd),
        head + "| robots t = 1 | 20,000 / 18,000 | 2,000 (10.0%) | - | 0.4 |\n"
        "| kitchen t = 5 | 1,000 / 1,100 | -100 (-10.0%) | - | no saving |\n",
    )
    os.remove(os.path.join(hd, "kitchen", "host.csv"))
    render_error(rtsim, "animation-hd", hd, [os.path.join("kitchen", "host.csv")])

# The integration table from what its programs print: its rows' texts and commands are the study
# file's.
with tempfile.TemporaryDirectory() as tmp:

    def printed(sub, text):
        os.makedirs(os.path.join(tmp, sub), exist_ok=True)
        with open(os.path.join(tmp, sub, "stdout.txt"), "w") as f:
            f.write(text)

    printed(
        "device", "Running main()\nframe 1: 73673 cycles\nframe 2: 71425 cycles\n[  PASSED  ]\n"
    )
    printed("frames", "frame 1: 100 cycles\n not: 5 cycles\nframe 2: 100 cycles trailing\n")
    printed("styles", "accept_later: 81494 cycles\nlt: 73488 cycles\n")
    for sub in ("platform-city", "platform-kitchen"):
        printed(
            sub,
            '{"hw": "x", "memory_bytes": 1}\n'
            + "".join(
                f'{{"frame": {k}, "cycles": {1000 * k}, "pixels": 14400, "interrupt_ns": 2000.5,'
                f' "wrong_records": {k - 1}}}\n'
                for k in (1, 2)
            ),
        )
    with open(os.path.join(src, "configs", "studies", "integration.yaml")) as f:
        study = yaml.safe_load(f)
    by = {r["dir"]: " ".join(r["program"]) for r in study["runs"]}
    text = {r["run"]: r["figure"] for r in study["table"]["rows"]}
    cells = {
        "device": "73,673, 71,425",
        "frames": "100",
        "styles": "81,494, 73,488",
        "platform-city": "1,000, 2,000",
        "platform-kitchen": "1,000, 2,000",
    }
    suffix = " at 14,400 pixels, two cameras (interrupt 2,000, 2,000 ns; wrong records 0, 1)"
    want = "| figure | cycles | measured by |\n|---|---|---|\n"
    for r in study["table"]["rows"]:
        figure = (
            text[r["run"]]
            + {
                "cycles": "",
                "named_cycles": ": accept_later, lt",
                "platform": suffix,
            }[r["cells"]]
        )
        want += f"| {figure} | {cells[r['run']]} | `{by[r['run']]}` |\n"
    same("integration", render(rtsim, "integration", tmp), want)
    check(len(study["table"]["rows"]) == 5, "integration: a row per program run")
    printed("platform-city", '{"hw": "x"}\n')
    render_error(rtsim, "integration", tmp, [os.path.join("platform-city", "stdout.txt")])

finish()
