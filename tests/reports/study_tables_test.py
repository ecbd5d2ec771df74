#!/usr/bin/env python3
"""The tables `rtsim study` renders in C++ (reports/study_tables.h) are byte for byte those of
scripts/docs_tables.py on the same runs, while both exist: each shipped study whose renderer is
ported, rendered by `rtsim study ID --table-only` from a run directory built here, against the
Python renderer refresh-docs.py used for it.

Usage: study_tables_test.py SOURCE_DIR RTSIM_BINARY"""

import csv
import json
import os
import subprocess
import sys
import tempfile

src, rtsim = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(src, "scripts"))
import docs_tables  # noqa: E402  (scripts/ has no package)

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def c_table(study, run_dir):
    r = subprocess.run(
        [rtsim, "study", study, "--out", run_dir, "--table-only"], capture_output=True, text=True
    )
    check(r.returncode == 0, f"rtsim study {study} --table-only: exit {r.returncode}: {r.stderr}")
    path = os.path.join(run_dir, "table.md")
    return open(path, newline="").read() if os.path.exists(path) else ""


def compare(study, run_dir, python_render):
    want = python_render(run_dir) + "\n"
    got = c_table(study, run_dir)
    check(got == want, f"{study}: C++ table differs from Python's:\n{got}\n--- Python:\n{want}")


def results(run_dir, cols, rows):
    os.makedirs(run_dir, exist_ok=True)
    with open(os.path.join(run_dir, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, cols, lineterminator="\n")
        w.writeheader()
        for r in rows:
            w.writerow({c: r.get(c, "") for c in cols})


with tempfile.TemporaryDirectory() as tmp:
    # A cache sweep: two scenes, a failed point (its reason quoted, with a comma), an empty metric,
    # numbers that round half to even and values that print in exponent form.
    metrics = [m for _, m, _ in docs_tables.CACHE_COLUMNS]
    # The arguments refresh-docs.py gave cache_table.
    for study, key, label, base, values in (
        ("cache-trv-l1", "hw.trv.l1.size_kb", "TRV L1 KB", "8", ["4", "8", "16"]),
        ("cache-ist-l1", "hw.ist.l1.size_kb", "IST L1 KB", "16", ["16", "2", "32"]),
        ("cache-l2-size", "variant", "L2", "table2-128k", ["trv-l2-32k", "table2-128k", "x"]),
        ("cache-l2-banks", "variant", "L2 banks", "banks-8", ["banks-8", "banks-2", "banks-16"]),
    ):
        rows = []
        for s, scene in enumerate(["kitchen", "robots"]):
            for i, v in enumerate(values):
                r = {"point": 3 * s + i, "id": f"p{3 * s + i:04}", "scene": scene, key: v}
                r["cycles_total"] = [1500.5, 1000, 2500.5, 1e7 + 0.5][(i + s) % 4]
                r.update(
                    {
                        m: [0.12345, 1e-05, 0.0625, 12.25, 2.5e3][j % 5]
                        for j, m in enumerate(metrics)
                    }
                )
                rows.append(r)
        rows[2]["ist_l2_bank_stall_cycles"] = ""
        rows[5] = {"point": 5, "id": "p0005", key: values[2], "failure": 'exit 1: "a, b"\nlast'}
        run_dir = os.path.join(tmp, study)
        results(
            run_dir, ["point", "id", "scene", key, "cycles_total"] + metrics + ["failure"], rows
        )
        compare(study, run_dir, docs_tables.cache_table(key, label, base))

    # The unpublished knobs: three scenes, a variant that failed with culling on, a zero.
    cols = ["point", "id", "scene", "variant", "run.lvb", "frame_ms_all", "failure"]
    rows, k = [], 0
    for scene in ["bunny", "kitchen", "robots"]:
        for v, ms in (("today", 2.0), ("trv-capacity-8", 2.5), ("fifo-4", 0.0)):
            for lvb, f in (("false", 1.0), ("true", 0.8)):
                r = {"point": k, "id": f"p{k:04}", "scene": scene, "variant": v, "run.lvb": lvb}
                r["frame_ms_all"] = ms * f + 0.0005 * k
                if scene == "kitchen" and v == "trv-capacity-8" and lvb == "true":
                    r = {
                        "point": k,
                        "id": f"p{k:04}",
                        "variant": v,
                        "run.lvb": lvb,
                        "failure": "killed",
                    }
                rows.append(r)
                k += 1
    for study in ("unpublished-knobs", "unpublished-knobs-hd"):
        results(os.path.join(tmp, study), cols, rows)
        compare(study, os.path.join(tmp, study), docs_tables.knob_table)

    # Reports a run wrote, from a heading on, its headings one level down.
    for study, name, first in (
        ("area-lights", "area_lights.md", "| scene"),
        ("ablation", "ablation.md", "Sweep `ablation.yaml`"),
        ("bvh", "bvh.md", "Sweep `bvh-study.yaml`"),
    ):
        run_dir = os.path.join(tmp, study)
        os.makedirs(run_dir)
        with open(os.path.join(run_dir, name), "w") as f:
            f.write(f"# Title\n\nabove\n\n{first} | x |\n|---|\n\n## A\n#not\n### B\ntext #\n\n\n")
        compare(study, run_dir, docs_tables.copy_markdown(name, first))
    # A report without the heading: one error naming the file, exit 2.
    r = subprocess.run(
        [rtsim, "study", "bvh", "--out", os.path.join(tmp, "area-lights"), "--table-only"],
        capture_output=True,
        text=True,
    )
    check(
        r.returncode == 2 and "bvh.md" in r.stderr, f"a missing report: {r.returncode} {r.stderr}"
    )


def point(run_dir, k, scene, row, total, ci, seconds):
    """A point of a reproduction or sweep: its report.json (cycles per phase, their intervals,
    host seconds) and row.json (its column values)."""
    d = os.path.join(run_dir, "points", f"p{k:04}")
    os.makedirs(d)
    r = {"scene": {"name": scene}, "host": {"seconds": {"total": seconds}}}
    for phase, share in (("total", 1.0), ("primary", 0.25), ("shadow", 0.75)):
        r[f"cycles_{phase}"] = total * share
        r[f"cycles_{phase}_ci95"] = ci * share
    with open(os.path.join(d, "report.json"), "w") as f:
        json.dump(r, f)
    with open(os.path.join(d, "row.json"), "w") as f:
        json.dump(row, f)


# The sampling validation: full reproductions and sampled ones (sK, nK), errors that miss, a
# sampled point missing, a setup without its culling-off run.
with tempfile.TemporaryDirectory() as tmp:
    for study, sub, variants in (
        ("sampling", "", ["off", "paper", "exact"]),
        ("sampling-bvh", "bvh", ["bvh8-off", "bvh8-paper", "bvh2-paper"]),
        ("sampling-bvh-formats", "bvh", ["cwbvh8-off", "cwbvh8-paper"]),
    ):
        run_dir = os.path.join(tmp, study)
        for seed, (error, ci, secs) in enumerate(
            [(0, 0, 80), (0.01, 20, 10), (-0.031, 20, 8), (0.004, 5, 9), (0.0, 30, 12)]
        ):
            name = ["full", "s1", "s2", "n1", "n2"][seed]
            k = 0
            for scene in ("kitchen", "robots"):
                for j, v in enumerate(variants):
                    if name == "s2" and scene == "robots" and j == 1:
                        continue  # a point that did not finish
                    total = (1000 - 100 * j) * (1 + error * (j + 1)) + 2.5 * k
                    point(
                        os.path.join(run_dir, name, sub),
                        k,
                        scene,
                        {"variant": v},
                        total,
                        ci,
                        secs + k,
                    )
                    k += 1
        compare(study, run_dir, lambda d, sub=sub: docs_tables.sampling_table(d, sub))

    # The cache sweeps sampled (directories full-NAME, s1-NAME), points told apart by a column.
    run_dir = os.path.join(tmp, "sampling-caches")
    for name, key, values in (
        ("trv-l1", "hw.trv.l1.size_kb", [2, 8]),
        ("ist-l1", "hw.ist.l1.size_kb", [16]),
        ("l2-size", "variant", ["table2-128k", "trv-l2-32k"]),
        ("l2-banks", "variant", ["banks-8"]),
    ):
        for sub, error, ci in (("full", 0, 0), ("s1", 0.02, 30), ("s2", -0.005, 10)):
            for k, v in enumerate(values):
                total = 2000 - 500 * k
                point(
                    os.path.join(run_dir, f"{sub}-{name}"),
                    k,
                    "kitchen",
                    {key: v},
                    total * (1 + error * (k + 1)),
                    ci,
                    30 if sub == "full" else 9 + k,
                )
    compare("sampling-caches", run_dir, docs_tables.sampling_sweeps_table)

    # The area-light sweep: points told apart by two columns, one a switch.
    run_dir = os.path.join(tmp, "sampling-area-lights")
    for sub, total in (("full-area-lights", 4000), ("s1-area-lights", 4040)):
        for k, (n, lvb) in enumerate([(16, True), (16, False), (64, True)]):
            point(
                os.path.join(run_dir, sub),
                k,
                "kitchen",
                {"scene.lights.area_from_points.samples": n, "run.lvb": lvb},
                total + k,
                100,
                40 if sub.startswith("full") else 20,
            )
    compare(
        "sampling-area-lights",
        run_dir,
        lambda d: docs_tables.sampling_sweeps_table(d, docs_tables.SAMPLED_AREA),
    )


def expect_cells(study, run_dir, python_render, expected):
    """The C++ table equals Python's and holds each expected cell (figures worked by hand)."""
    compare(study, run_dir, python_render)
    table = open(os.path.join(run_dir, "table.md")).read()
    for cells in expected:
        check(cells in table, f"{study}: no '{cells}' in:\n{table}")


# Worked by hand: a full reproduce and two sampled ones of two setups, a sampled cache sweep, an
# area-light point.
with tempfile.TemporaryDirectory() as tmp:
    for sub, k, variant, total, ci, secs in (
        ("full", 0, "off", 1000, 0, 80),
        ("full", 1, "exact", 900, 0, 80),
        ("s1", 0, "off", 1010, 20, 10),  # +1%, held
        ("s1", 1, "exact", 930, 20, 10),  # +3.3%, missed
        ("s2", 0, "off", 990, 20, 8),
        ("s2", 1, "exact", 900, 20, 8),
    ):
        point(os.path.join(tmp, sub), k, "kitchen", {"variant": variant}, total, ci, secs)
    expect_cells(
        "sampling",
        tmp,
        docs_tables.sampling_table,
        [
            "| kitchen, off | 1,000 | +1.00% / 2.00% | -1.00% / 2.00% | 9.0x |",
            "| kitchen, exact | 900 | +3.33% / 2.22% (missed) | +0.00% / 2.22% | 9.0x |",
            "4 sampled frames: the largest error 3.33%, 3 of 4 within 2%; the 95% interval held "
            "the full run's frame in 3 of 4 (missed: kitchen, exact, seed 1), its primary phase "
            "in 3, its shadow phase in 3; host time 9.0x less (median; from 8.0x to 10.0x).",
            "| kitchen, exact | 10.00% | -2.08 pt | -0.91 pt |",  # 1 - 930 / 1010, 1 - 900 / 990
        ],
    )
    for sub, k, size, total, ci, secs in (
        ("full-trv-l1", 0, 2, 2000, 0, 30),
        ("full-trv-l1", 1, 8, 1000, 0, 20),
        ("s1-trv-l1", 0, 2, 2050, 40, 10),  # +2.5%, missed
        ("s1-trv-l1", 1, 8, 990, 30, 10),
    ):
        point(os.path.join(tmp, sub), k, "kitchen", {"hw.trv.l1.size_kb": size}, total, ci, secs)
    for name in ("ist-l1", "l2-size", "l2-banks"):
        for sub in ("full", "s1"):
            os.makedirs(os.path.join(tmp, f"{sub}-{name}", "points"))
    expect_cells(
        "sampling-caches",
        tmp,
        docs_tables.sampling_sweeps_table,
        [
            "| trv-l1 | kitchen | TRV L1 KB 2 | 2,000 | +2.50% / 2.00% (missed) | 3.0x |",
            "| trv-l1 | kitchen | TRV L1 KB 8 | 1,000 | -1.00% / 3.00% | 2.0x |",
            "2 sampled points: the largest error 2.50%, 1 of 2 within 2%; the 95% interval held "
            "the full run's frame in 1 of 2 (missed: trv-l1, kitchen, 2, seed 1)",
        ],
    )
    for sub, total in (("full-area-lights", 4000), ("s1-area-lights", 4040)):
        row = {"scene.lights.area_from_points.samples": 16, "run.lvb": True}
        point(os.path.join(tmp, sub), 0, "kitchen", row, total, 100, 40 if "full" in sub else 20)
    expect_cells(
        "sampling-area-lights",
        tmp,
        lambda d: docs_tables.sampling_sweeps_table(d, docs_tables.SAMPLED_AREA),
        ["| area-lights | kitchen | N, culling 16, on | 4,000 | +1.00% / 2.50% | 2.0x |"],
    )


def frames_files(run_dir, frames):
    """An `rtsim animate` directory's frames.csv and host.csv: `frames` a list of dicts (None an
    empty cell); host.csv lacks the last frame's time."""
    os.makedirs(run_dir)
    cols = list(frames[0])
    results(run_dir, cols, [{k: "" if v is None else v for k, v in f.items()} for f in frames])
    os.rename(os.path.join(run_dir, "results.csv"), os.path.join(run_dir, "frames.csv"))
    hcols = ["time", "kdtree_seconds", "lvb_seconds", "simulate_seconds_off"]
    host = [
        {
            "time": f["time"],
            "kdtree_seconds": 0.2 + f["time"] / 100,
            "lvb_seconds": 0.45,
            "simulate_seconds_off": 3,
        }
        for f in frames[:-1]
    ]
    results(run_dir, hcols, host)
    os.rename(os.path.join(run_dir, "results.csv"), os.path.join(run_dir, "host.csv"))


def frame(t, off, on, k, lazy=True, checked=None):
    """One frame: cycles off and on, the LVB's work growing with `k`, a lazy rebuild's when
    `lazy`, the reference check's mismatches when checked."""
    return {
        "time": t,
        "cycles_off": off,
        "cycles_on": on,
        "culled_share": 0.1 + 0.01 * k,
        "lvb_nodes_visited": 3.5e6 + 1e4 * k,
        "lvb_region_tests": 3.7e6 + 2.5e4 * k,
        "lvb_pair_tests": 1.1e6 - 1e3 * k,
        "lazy_dirty_pairs": 100 * k if lazy else None,
        "lazy_pairs": (1000 if k else 0) if lazy else None,
        "lazy_dirty_tests": 1.5e6 + k if lazy else None,
        "lazy_region_tests": 3e5 if lazy else None,
        "lazy_pair_tests": 2.5e5 if lazy else None,
        "check_mismatched_pixels": checked,
    }


# The animations: per scene, frames with a saving, a loss, none; a scene without a lazy rebuild;
# host.csv without the last frame. The 1920x1080 study beside the 480x270 one, which lacks a time.
with tempfile.TemporaryDirectory() as tmp:
    robots = [
        frame(0, 3.4e6, 3.2e6, 0, checked=0),
        frame(0.5, 2.2e6, 2.3e6, 1),
        frame(1, 5.3e6, 5.3e6, 2, checked=3),
        frame(1.5, 4.1e6 + 0.5, 4e6, 3),
    ]
    kitchen = [
        frame(0, 1.7e6, 1.69e6, 4, lazy=False, checked=1),
        frame(10, 7.2e6, 7.0e6, 5, lazy=False),
    ]
    frames_files(os.path.join(tmp, "animation", "robots"), robots)
    frames_files(os.path.join(tmp, "animation", "kitchen"), kitchen)
    compare("animation", os.path.join(tmp, "animation"), docs_tables.animation_table)
    frames_files(
        os.path.join(tmp, "animation-hd", "robots"),
        [frame(0, 3.4e7, 3.1e7, 0), frame(1, 5e7, 5e7, 1), frame(2, 6e7, 5.9e7, 2)],
    )
    frames_files(
        os.path.join(tmp, "animation-hd", "kitchen"),
        [frame(0, 3.8e7, 3.7e7, 0), frame(10, 8.7e7, 8.8e7, 1)],
    )
    compare("animation-hd", os.path.join(tmp, "animation-hd"), docs_tables.animation_hd_table)

    # The integration figures: tests' `NAME: N cycles` lines among others, examples/platform's
    # JSON lines (its first line not a frame).
    run_dir = os.path.join(tmp, "integration")
    outputs = {
        "device": "[ RUN ] x\nframe 0: 73673 cycles\nframe 1: 71425 cycles\n not: 5 cycles\n",
        "frames": "a: 1 cycles\nb: 2 cycles\nc: 3 cycles trailing\nd: 1234567 cycles\n",
        "styles": "accept_later: 81494 cycles\nlt_adapter: 1390802 cycles\n",
        "platform-city": '{"hw": "x"}\n{"frame": 1, "cycles": 73488, "interrupt_ns": 75768.5, '
        '"pixels": 14400, "wrong_records": 0}\n{"frame": 2, "cycles": 71082, '
        '"interrupt_ns": 148050.25, "pixels": 14400, "wrong_records": 2}\n',
        "platform-kitchen": '{"frame": 1, "cycles": 259352, "interrupt_ns": 274872.0, '
        '"pixels": 1000000, "wrong_records": 0}\n{"frame": 2, "cycles": 221908, '
        '"interrupt_ns": 1497980.5, "pixels": 1000000, "wrong_records": 0}\n',
    }
    for sub, text in outputs.items():
        os.makedirs(os.path.join(run_dir, sub))
        with open(os.path.join(run_dir, sub, "stdout.txt"), "w") as f:
            f.write(text)
    compare("integration", run_dir, docs_tables.integration_table)

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
