#!/usr/bin/env python3
"""scripts/refresh-docs.py without running a study: its renderers on a sweep's results.csv, the
block replacement in a doc (only between its markers, the rest untouched), and that every block
the script knows is in its doc and every generated block in docs/ belongs to a study."""

import csv
import importlib.util
import os
import re
import sys
import tempfile

src = sys.argv[1]
spec = importlib.util.spec_from_file_location("refresh", os.path.join(src, "scripts", "refresh-docs.py"))
refresh = importlib.util.module_from_spec(spec)
spec.loader.exec_module(refresh)
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


with tempfile.TemporaryDirectory() as tmp:
    cols = ["point", "id", "scene", "hw.trv.l1.size_kb", "cycles_total"] + [m for _, m, _ in refresh.CACHE_COLUMNS] + ["failure"]
    with open(os.path.join(tmp, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, cols)
        w.writeheader()
        for i, (kb, cyc) in enumerate([("4", 1500), ("8", 1000), ("16", 950)]):
            row = {c: "0.5" for c in cols}
            row.update({"point": i, "id": f"p{i:04}", "scene": "kitchen", "hw.trv.l1.size_kb": kb,
                        "cycles_total": cyc, "failure": ""})
            w.writerow(row)
    table = refresh.cache_table("hw.trv.l1.size_kb", "TRV L1 KB", "8")(tmp)
    lines = table.splitlines()
    check(lines[0].startswith("| scene | TRV L1 KB | cycles | vs Table 2 |"), "cache table header")
    check("| kitchen | 4 | 1,500 | +50.0% | 50.0% |" in table, "the 4 KB row against the 8 KB one:\n" + table)
    check("| kitchen | 16 | 950 | -5.0% |" in table, "the 16 KB row")
    doc = os.path.join(tmp, "doc.md")
    with open(doc, "w") as f:
        f.write("before\n<!-- generated: x -->\nold\n<!-- end generated: x -->\nafter\n")
    refresh.replace_block(doc, "x", "new table")
    check(open(doc).read() == "before\n<!-- generated: x -->\nnew table\n<!-- end generated: x -->\nafter\n",
          "block replaced, the rest untouched")
    try:
        refresh.replace_block(doc, "y", "z")
        failures.append("a missing block must be an error")
    except SystemExit as e:
        check("no block" in str(e), "the error names the block")

ids = {s.id for s in refresh.STUDIES}
for s in refresh.STUDIES:
    text = open(os.path.join(src, s.doc)).read()
    check(f"<!-- generated: {s.id} -->" in text and f"<!-- end generated: {s.id} -->" in text,
          f"{s.doc} has no block for {s.id}")
for name in os.listdir(os.path.join(src, "docs")):
    if name.endswith(".md"):
        for ident in re.findall(r"<!-- generated: ([\w-]+) -->", open(os.path.join(src, "docs", name)).read()):
            check(ident in ids, f"docs/{name}: block {ident} has no study in refresh-docs.py")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
