#!/usr/bin/env python3
"""The tables `rtsim study` renders from sweeps and reproductions (reports/study_tables.h) hold
what the runs' files say: each shipped study's table, rendered by `rtsim study ID --table-only`
from a run directory built here, has a row per point in the files' order, each cell the file's
figure as the table's format writes it, and lines worked out by hand; a file that lacks what the
table needs is one error naming it. (Animations and programs: study_run_tables_test.py.)

Usage: study_tables_test.py SOURCE_DIR RTSIM_BINARY"""

import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from study_check import (  # noqa: E402  (tests/ has no package)
    check,
    expect_lines,
    finish,
    point,
    render,
    render_error,
    rows,
    study_table,
    write_csv,
)

src, rtsim = sys.argv[1], sys.argv[2]
FORMATS = {
    "int": lambda v: f"{round(v):,}",
    "pct": lambda v: f"{100 * v:.1f}%",
    "1": "{:.1f}".format,
}


def cache_study(tmp, study, values):
    """A cache sweep: two scenes, a failed point (its reason quoted, with a comma and a line
    break), an empty metric, numbers that round half to even; checked row by row."""
    t = study_table(src, study)
    key, metrics = t["key"], [c["metric"] for c in t["columns"]]
    data = []
    for s, scene in enumerate(["kitchen", "robots"]):
        for i, v in enumerate(values):
            r = {"point": 3 * s + i, "id": f"p{3 * s + i:04}", "scene": scene, key: v}
            r["cycles_total"] = [1500.5, 1000, 2500, 1e7 + 0.5][(i + s) % 4]
            r.update(
                {m: [0.12345, 1e-05, 0.0625, 12.25, 2.5e3][j % 5] for j, m in enumerate(metrics)}
            )
            data.append(r)
    data[2][metrics[6]] = ""
    data[5] = {"point": 5, "id": "p0005", "scene": "robots", key: values[2]}
    data[5]["failure"] = 'exit 1: "a, b"\nlast'
    run_dir = os.path.join(tmp, study)
    cols = ["point", "id", "scene", key, "cycles_total"] + metrics + ["failure"]
    write_csv(os.path.join(run_dir, "results.csv"), cols, data)
    table = render(rtsim, study, run_dir)
    cells = rows(table.replace("\nlast |", " last |"))
    head = ["scene", t["label"], "cycles", "vs Table 2"] + [c["title"] for c in t["columns"]]
    check(cells[:1] == [head], f"{study}: header {cells[:1]}")
    check(len(cells) == 1 + len(data), f"{study}: {len(cells) - 1} rows for {len(data)} points")
    base = {r["scene"]: r["cycles_total"] for r in data if r[key] == str(t["baseline"])}
    for r, got in zip(data, cells[1:]):
        if r.get("failure"):
            check(got == [r["scene"], r[key], 'failed: exit 1: "a, b" last'], f"failed: {got}")
            continue
        want = [r["scene"], r[key], f"{round(r['cycles_total']):,}"]
        want += [f"{100 * (r['cycles_total'] / base[r['scene']] - 1):+.1f}%"]
        want += [
            FORMATS[c["format"]](r[c["metric"]]) if r[c["metric"]] != "" else "-"
            for c in t["columns"]
        ]
        check(got == want, f"{study}: row {got}, expected {want}")
    return table


with tempfile.TemporaryDirectory() as tmp:
    for study, values in (
        ("cache-trv-l1", ["4", "8", "16"]),
        ("cache-ist-l1", ["16", "2", "32"]),
        ("cache-l2-size", ["trv-l2-32k", "table2-128k", "x"]),
        ("cache-l2-banks", ["banks-8", "banks-2", "banks-16"]),
    ):
        table = cache_study(tmp, study, values)
    # Worked by hand (cache-l2-banks, baseline banks-8): 1500.5 cycles round to even; the
    # metric columns pct, pct, pct, pct, 1, 1, int, 1 (the empty one a dash).
    expect_lines(
        "cache-l2-banks",
        table,
        [
            "| kitchen | banks-8 | 1,500 | +0.0% | 12.3% | 0.0% | 6.2% | 1225.0% | 2500.0 | 0.1 |"
            " 0 | 0.1 |",
            "| kitchen | banks-16 | 2,500 | +66.6% | 12.3% | 0.0% | 6.2% | 1225.0% | 2500.0 | 0.1 |"
            " - | 0.1 |",
            "| robots | banks-8 | 1,000 | +0.0% | 12.3% | 0.0% | 6.2% | 1225.0% | 2500.0 | 0.1 |"
            " 0 | 0.1 |",
        ],
    )
    render_error(rtsim, "cache-trv-l1", os.path.join(tmp, "nothing"), ["results.csv"])

    # The unpublished knobs: three scenes, a variant that failed with culling on, a zero.
    cols = ["point", "id", "scene", "variant", "run.lvb", "frame_ms_all", "failure"]
    data, k = [], 0
    for scene in ["bunny", "kitchen", "robots"]:
        for v, ms in (("today", 2.0), ("trv-capacity-8", 2.5), ("fifo-4", 0.0)):
            for lvb, f in (("false", 1.0), ("true", 0.8)):
                r = {"point": k, "id": f"p{k:04}", "scene": scene, "variant": v, "run.lvb": lvb}
                r["frame_ms_all"] = ms * f + (0.001 * k if ms else 0)
                if scene == "kitchen" and v == "trv-capacity-8" and lvb == "true":
                    r["frame_ms_all"], r["failure"] = "", "killed"
                data.append(r)
                k += 1
    for study in ("unpublished-knobs", "unpublished-knobs-hd"):
        write_csv(os.path.join(tmp, study, "results.csv"), cols, data)
        table = render(rtsim, study, os.path.join(tmp, study))
        check(len(rows(table)) == 4, f"{study}: a row per variant:\n{table}")
        expect_lines(
            study,
            table,
            [
                "| variant | bunny off / on (ms) | kitchen off / on (ms) | robots off / on (ms) |"
                " bunny off vs today | kitchen off vs today | robots off vs today |",
                "| today | 2.000 / 1.601 | 2.006 / 1.607 | 2.012 / 1.613 | +0.0% | +0.0% | +0.0% |",
                # 2.502 / 2.000, 2.508 / 2.006, 2.514 / 2.012
                "| trv-capacity-8 | 2.502 / 2.003 | failed | 2.514 / 2.015 | +25.1% | +25.0% |"
                " +25.0% |",
                "| fifo-4 | 0.000 / 0.000 | 0.000 / 0.000 | 0.000 / 0.000 | - | - | - |",
            ],
        )

    # Reports a run wrote, from a heading on, its headings one level down.
    for study in ("area-lights", "ablation", "bvh"):
        t = study_table(src, study)
        run_dir = os.path.join(tmp, study)
        os.makedirs(run_dir)
        with open(os.path.join(run_dir, t["file"]), "w") as f:
            f.write(
                f"# Title\n\nabove\n\n{t['from']} | x |\n|---|\n\n## A\n#not\n### B\ntext #\n\n"
            )
        want = f"{t['from']} | x |\n|---|\n\n### A\n#not\n#### B\ntext #\n"
        check(render(rtsim, study, run_dir) == want, f"{study}: copied report")
    # A report without the heading: one error naming the file, exit 2.
    render_error(rtsim, "bvh", os.path.join(tmp, "area-lights"), ["bvh.md"])


def plan_sections(table):
    """A sampling table's sections by title: their table rows and summary line."""
    out, title = {}, None
    for line in table.splitlines():
        if line.startswith("Culling's"):
            out[title]["reduction"] = True
        elif line.endswith(":") and not line.startswith("|"):
            title = line
            out[title] = {"rows": [], "summary": []}
        elif title and line.startswith("| ") and "reduction" not in out[title]:
            out[title]["rows"].append(line)
        elif title and "sampled frames" in line:
            out[title]["summary"].append(line)
    return out


# The sampling validation: full reproductions and sampled ones (sK, nK), errors that miss, a
# sampled point missing, a setup without its culling-off run.
with tempfile.TemporaryDirectory() as tmp:
    for study, sub, variants in (
        ("sampling", "", ["off", "paper", "exact"]),
        ("sampling-bvh", "bvh", ["bvh8-off", "bvh8-paper", "bvh2-paper"]),
        ("sampling-bvh-formats", "bvh", ["cwbvh8-off", "cwbvh8-paper"]),
    ):
        run_dir = os.path.join(tmp, study)
        for name, error, ci, secs in [
            ("full", 0, 0, 80),
            ("s1", 0.01, 20, 10),
            ("s2", -0.031, 20, 8),
            ("n1", 0.004, 5, 9),
            ("n2", 0.0, 30, 12),
        ]:
            k = 0
            for scene in ("kitchen", "robots"):
                for j, v in enumerate(variants):
                    if name == "s2" and scene == "robots" and j == 1:
                        continue  # a point that did not finish
                    total = (1000 - 100 * j) * (1 + error * (j + 1)) + 2.5 * k
                    row = {"variant": v}
                    point(os.path.join(run_dir, name, sub), k, scene, row, total, ci, secs + k)
                    k += 1
        sections = plan_sections(render(rtsim, study, run_dir))
        setups = 2 * len(variants)
        check(len(sections) == 2, f"{study}: two plans, got {list(sections)}")
        for title, sampled in zip(sections, (2 * setups - 1, 2 * setups)):
            s = sections[title]
            check(len(s["rows"]) == 1 + setups, f"{study} {title}: {len(s['rows'])} rows")
            check(
                len(s["summary"]) == 1 and s["summary"][0].startswith(f"{sampled} sampled frames"),
                f"{study} {title}: summary {s['summary']}",
            )
        missing = [
            r
            for r in sections[list(sections)[0]]["rows"]
            if r.startswith(f"| robots, {variants[1]} |")
        ]
        check(len(missing) == 1 and missing[0].split(" | ")[3] == "-", f"{study}: {missing}")

# Worked by hand: a full reproduction and two sampled ones of two setups, a sampled cache sweep,
# an area-light point.
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
    expect_lines(
        "sampling",
        render(rtsim, "sampling", tmp),
        [
            "Strata in issue order (`run.sample_strata: issue`):",
            "| setup | full run (cycles) | seed 1: error / interval | seed 2: error / interval |"
            " speedup (median) |",
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
    expect_lines(
        "sampling-caches",
        render(rtsim, "sampling-caches", tmp),
        [
            "| trv-l1 | kitchen | TRV L1 KB 2 | 2,000 | +2.50% / 2.00% (missed) | 3.0x |",
            "| trv-l1 | kitchen | TRV L1 KB 8 | 1,000 | -1.00% / 3.00% | 2.0x |",
            "2 sampled points: the largest error 2.50%, 1 of 2 within 2%; the 95% interval held "
            "the full run's frame in 1 of 2 (missed: trv-l1, kitchen, 2, seed 1), its primary "
            "phase in 1, its shadow phase in 1; host time 2.5x less (median; from 2.0x to 3.0x).",
        ],
    )
    for sub, total in (("full-area-lights", 4000), ("s1-area-lights", 4040)):
        row = {"scene.lights.area_from_points.samples": 16, "run.lvb": True}
        point(os.path.join(tmp, sub), 0, "kitchen", row, total, 100, 40 if "full" in sub else 20)
    expect_lines(
        "sampling-area-lights",
        render(rtsim, "sampling-area-lights", tmp),
        ["| area-lights | kitchen | N, culling 16, on | 4,000 | +1.00% / 2.50% | 2.0x |"],
    )
    # A study that has not run: one error naming the directory it looked for.
    render_error(rtsim, "sampling", os.path.join(tmp, "nothing"), ["full/points"])

# The path-traced frames study (reports/study_paths_table.h): one scene on one machine, Whitted and
# path-traced frames, culling off / paper / exact; a Whitted frame has no bounces ("-").
with tempfile.TemporaryDirectory() as tmp:
    cols = ["point", "scene", "variant", "run.integrator", "cycles_total", "rays_primary"]
    cols += ["rays_reflection", "rays_bounce", "rays_shadow", "shadow_culled_rate"]
    cols += [f"bounce{b}_culled_rate" for b in range(4)]
    cols += ["bounce0_cycles_per_ray", "bounce1_cycles_per_ray", "dram_bytes_per_ray"]
    cols += ["traversal_l1_hit_rate", "traversal_l2_hit_rate", "failure"]
    data = []
    for culling, whitted, path in (("off", 1000, 4000), ("paper", 990, 4000), ("exact", 900, 4200)):
        base = {"scene": "s", "variant": "kd-" + culling, "rays_primary": 100}
        base.update({"rays_reflection": 0, "dram_bytes_per_ray": 12.34})
        base.update({"traversal_l1_hit_rate": 0.9, "traversal_l2_hit_rate": 0.5})
        data.append(
            dict(base, **{"run.integrator": "whitted", "cycles_total": whitted, "rays_shadow": 200})
        )
        data.append(
            dict(
                base,
                **{"run.integrator": "path", "cycles_total": path, "rays_shadow": 300},
                rays_reflection=5,
                rays_bounce=45,
                bounce0_culled_rate=0.25,
                bounce1_culled_rate=0.125,
                bounce2_culled_rate=0.5,
                bounce3_culled_rate=0,
                bounce0_cycles_per_ray=1234.4,
                bounce1_cycles_per_ray=99.5,
            )
        )
    for k, d in enumerate(data):
        d["point"] = k
        d["shadow_culled_rate"] = 0.1 if d["variant"] == "kd-exact" else 0.0
    write_csv(os.path.join(tmp, "results.csv"), cols, data)
    got = render(rtsim, "paths", tmp)
    expect_lines(
        "paths",
        got,
        [
            "| s | kd | whitted | 100 | 0 | 200 | 1,000 | -1.0% | -10.0% | 10.0% |",
            "| s | kd | path | 100 | 50 | 300 | 4,000 | +0.0% | +5.0% | 10.0% |",
            "| s | kd | whitted | - | - | - | - | - | - | 12.3 | 90.0% | 50.0% |",
            "| s | kd | path | 25.0% | 12.5% | 50.0% | 0.0% | 1,234 | 100 | 12.3 | 90.0% | 50.0% |",
        ],
    )
    write_csv(
        os.path.join(tmp, "results.csv"), cols, [d for d in data if d["variant"] != "kd-paper"]
    )
    render_error(rtsim, "paths", tmp, ["results.csv", "culling paper"])


# The energy study (reports/study_energy_table.h): one scene on one machine, Whitted and
# path-traced frames on two DRAMs, culling off / paper / exact.
with tempfile.TemporaryDirectory() as tmp:
    parts = ["energy_units_uj", "energy_caches_uj", "energy_links_uj"]
    parts += ["energy.dram.dynamic_uj", "energy.dram.static_uj"]
    cols = ["point", "scene", "variant", "run.integrator", "hw.dram.preset", "frame_ms_all"]
    cols += ["energy_uj", "edp", "power_w", "energy_nj_per_ray", "energy_static_uj"] + parts
    cols += ["failure"]
    data = []
    # A frame's energy (uJ), time (ms), DRAM background and SRAM leakage (uJ) with each culling
    # mode, before scaling by m: off 1000 uJ in 2 ms, its parts 10/20/5/15/50%, 51% static;
    # paper -1% energy and time.
    for integrator, dram, m, exact in (
        ("whitted", "g3", 1, (900, 1.8, 450, 9)),
        ("whitted", "lp4", 2, (950, 1.92, 490, 10)),
        ("path", "g3", 4, (800, 1.5, 430, 8)),
    ):
        modes = (("off", 1000, 2.0, 500, 10), ("paper", 990, 1.98, 495, 10), ("exact",) + exact)
        for culling, e, ms, bg, leak in modes:
            r = {"scene": "s", "variant": "kd-" + culling, "run.integrator": integrator}
            r.update({"hw.dram.preset": dram, "frame_ms_all": ms * m, "energy_uj": e * m})
            r.update({"edp": e * ms * m * m, "power_w": e / ms / 1000})
            r["energy_nj_per_ray"], r["energy_static_uj"] = 12.345 * m, (bg + leak) * m
            r.update(zip(parts, [0.1 * e * m, 0.2 * e * m, 0.05 * e * m, 0.15 * e * m, bg * m]))
            r[parts[0]] += (e - bg) * m - sum(r[k] for k in parts[:4])
            data.append(r)
    for k, d in enumerate(data):
        d["point"] = k
    write_csv(os.path.join(tmp, "results.csv"), cols, data)
    got = render(rtsim, "energy", tmp)
    check(got.count("| scene | machine | DRAM |") == 4, f"energy: two tables a frame:\n{got}")
    expect_lines(
        "energy",
        got,
        [
            "| s | kd | g3 | 2.000 | 1,000 | 10.0% | 20.0% | 5.0% | 15.0% | 50.0% | 0.50 | 12.3 |",
            "| s | kd | lp4 | 4.000 | 2,000 | 10.0% | 20.0% | 5.0% | 15.0% | 50.0% | 0.50 | 24.7 |",
            "| s | kd | g3 | 8.000 | 4,000 | 10.0% | 20.0% | 5.0% | 15.0% | 50.0% | 0.50 | 49.4 |",
            # EDP: 990 x 1.98 against 1000 x 2 is -1.98%, 900 x 1.8 -19%; the exact mode saves 100
            # of 1000 uJ, 51 of them static (510 -> 459).
            "| s | kd | g3 | -1.0% | -1.0% | -2.0% | -10.0% | -10.0% | -19.0% | -5.1 pt"
            " | -4.9 pt |",
            # 950 x 1.92 = 1824: -8.8%; 50 uJ saved, 10 of them static (510 -> 500).
            "| s | kd | lp4 | -1.0% | -1.0% | -2.0% | -5.0% | -4.0% | -8.8% | -1.0 pt | -4.0 pt |",
            # 800 x 1.5 = 1200: -40%; 200 uJ saved, 72 of them static (510 -> 438).
            "| s | kd | g3 | -1.0% | -1.0% | -2.0% | -20.0% | -25.0% | -40.0% | -7.2 pt"
            " | -12.8 pt |",
        ],
    )
    whitted = got[: got.index("`path` frames without culling")]
    check(whitted.count("| s | kd | g3 |") == 2, f"energy: Whitted tables:\n{whitted}")
    data[5]["energy_static_uj"] = ""  # the lp4 Whitted frame's exact point
    write_csv(os.path.join(tmp, "results.csv"), cols, data)
    render_error(rtsim, "energy", tmp, ["results.csv", "energy_static_uj"])
    write_csv(os.path.join(tmp, "results.csv"), cols, data[:4] + data[5:])
    render_error(rtsim, "energy", tmp, ["results.csv", "lp4", "culling paper"])

finish()
