#!/usr/bin/env python3
"""scripts/docs_tables.py's renderers on a sweep's results.csv, an animation's frames and
programs' output (the sampled runs' tables: study_tables_test.py), and that every block a study
names (configs/studies/) is in its doc and every generated block in docs/ belongs to a study."""

import csv
import os
import re
import sys
import tempfile

src = sys.argv[1]
sys.path.insert(0, os.path.join(src, "scripts"))
import docs_tables  # noqa: E402  (scripts/ has no package)

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


with tempfile.TemporaryDirectory() as tmp:
    cols = (
        ["point", "id", "scene", "hw.trv.l1.size_kb", "cycles_total"]
        + [m for _, m, _ in docs_tables.CACHE_COLUMNS]
        + ["failure"]
    )
    with open(os.path.join(tmp, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, cols)
        w.writeheader()
        for i, (kb, cyc) in enumerate([("4", 1500), ("8", 1000), ("16", 950)]):
            row = {c: "0.5" for c in cols}
            row.update(
                {
                    "point": i,
                    "id": f"p{i:04}",
                    "scene": "kitchen",
                    "hw.trv.l1.size_kb": kb,
                    "cycles_total": cyc,
                    "failure": "",
                }
            )
            w.writerow(row)
    table = docs_tables.cache_table("hw.trv.l1.size_kb", "TRV L1 KB", "8")(tmp)
    lines = table.splitlines()
    check(lines[0].startswith("| scene | TRV L1 KB | cycles | vs Table 2 |"), "cache table header")
    check(
        "| kitchen | 4 | 1,500 | +50.0% | 50.0% |" in table,
        "the 4 KB row against the 8 KB one:\n" + table,
    )
    check("| kitchen | 16 | 950 | -5.0% |" in table, "the 16 KB row")

# An animation's frames: the 480x270 table's medians and ranges, the HD table against it.
with tempfile.TemporaryDirectory() as tmp:

    def frames(run_dir, rows):
        os.makedirs(run_dir)
        keys = [
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
        with open(os.path.join(run_dir, "frames.csv"), "w") as f:
            f.write(",".join(keys) + "\n" + "".join(",".join(map(str, r)) + "\n" for r in rows))
        with open(os.path.join(run_dir, "host.csv"), "w") as f:
            f.write("time,kdtree_seconds,lvb_seconds,simulate_seconds_off,simulate_seconds_on\n")
            f.write("".join(f"{r[0]},0.25,0.5,1,1\n" for r in rows))

    small = os.path.join(tmp, "animation")
    for scene in ["robots", "kitchen"]:
        frames(
            os.path.join(small, scene),
            [
                (0, 1000, 900, 0.1, 10, 200, 0, "", "", "", "", "", 0),
                (1, 2000, 1900, 0.3, 20, 400, 100, 5, 20, 30, 20, 10, ""),
                (2, 4000, 3600, 0.2, 30, 300, 200, 10, 20, 50, 10, 20, 3),
            ],
        )
        frames(
            os.path.join(tmp, "animation-hd", scene),
            [(1, 20000, 18000, 0.3, 20, 400, 400, "", "", "", "", "", "")],
        )
    table = docs_tables.animation_table(small)
    for row in [
        "| cycles, culling off | 2,000 (0.00-0.00 M) |",
        "| cycles culling saves | 100 (100-400), 10.0% (5.0-10.0%) |",  # 10%, 5%, 10%
        "| shadow rays culled | 20.0% (10.0-30.0%) |",
        "| LVB tests (region + pair) per saved cycle | 5.0 (1.2-5.0) |",  # 500 / 100; 2, 5, 1.25
        "| lazy: dirty pairs | 37.5% (25.0-50.0%) |",
        "| lazy tests per saved cycle | 0.7 (0.2-0.6) |",  # median(60, 80) / 100; 0.6, 0.2
        "| lazy: tests (dirty + region + pair) | 0.00 M (14% of full;",  # 70 / 500
        "| `--check-every 5`: pixels differing from the reference | 3 in 2 frames x 2 runs |",
    ]:
        check(
            row.split(" | ")[0] in table
            and any(line.startswith(row) for line in table.splitlines()),
            f"animation row {row}:\n{table}",
        )
    hd = docs_tables.animation_hd_table(os.path.join(tmp, "animation-hd"))
    check(
        "| robots t = 1 | 20,000 / 18,000 | 2,000 (10.0%) | 20.0 | 0.4 |" in hd,
        "the HD row:\n" + hd,
    )

# The integration table from what its programs print.
with tempfile.TemporaryDirectory() as tmp:

    def printed(sub, text):
        os.makedirs(os.path.join(tmp, sub))
        with open(os.path.join(tmp, sub, "stdout.txt"), "w") as f:
            f.write(text)

    printed(
        "device", "Running main()\nframe 1: 73673 cycles\nframe 2: 71425 cycles\n[  PASSED  ]\n"
    )
    printed("frames", "frame 1: 100 cycles\nframe 2: 100 cycles\n")
    printed("styles", "accept_later: 81494 cycles\nlt: 73488 cycles\n")
    for sub in ("platform-city", "platform-kitchen"):
        printed(
            sub,
            '{"hw": "x", "memory_bytes": 1}\n'
            + "".join(
                f'{{"frame": {k}, "cycles": {1000 * k}, "pixels": 14400, "interrupt_ns": 2000.4,'
                f' "wrong_records": 0}}\n'
                for k in (1, 2)
            ),
        )
    table = docs_tables.integration_table(tmp)
    for cells in [
        "the setup's again | 73,673, 71,425 |",
        "(turned, its own frame buffer) | 100, 100 |",
        ": accept_later, lt | 81,494, 73,488 |",
        "city at 14,400 pixels, two cameras (interrupt 2,000, 2,000 ns; wrong records 0, 0) | "
        "1,000, 2,000 |",
    ]:
        check(cells in table, f"integration cells {cells}:\n{table}")

# configs/studies/ID.yaml names its doc (relative to the file) in a `doc:` line.
studies = os.path.join(src, "configs", "studies")
ids = set()
for name in sorted(os.listdir(studies)):
    ident = name[: -len(".yaml")]
    ids.add(ident)
    doc = re.search(r"^doc: (\S+)$", open(os.path.join(studies, name)).read(), re.M)
    check(doc is not None, f"configs/studies/{name} has no doc")
    text = open(os.path.normpath(os.path.join(studies, doc.group(1)))).read() if doc else ""
    figure = re.search(r"^  to: (\S+)$", open(os.path.join(studies, name)).read(), re.M)
    check(
        not figure or os.path.exists(os.path.join(studies, figure.group(1))),
        f"{name}: no figure {figure and figure.group(1)}",
    )
    check(
        f"<!-- generated: {ident} -->" in text and f"<!-- end generated: {ident} -->" in text,
        f"{name}: its doc has no block for {ident}",
    )
for name in os.listdir(os.path.join(src, "docs")):
    if name.endswith(".md"):
        for ident in re.findall(
            r"<!-- generated: ([\w-]+) -->", open(os.path.join(src, "docs", name)).read()
        ):
            check(ident in ids, f"docs/{name}: block {ident} has no study in configs/studies/")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
