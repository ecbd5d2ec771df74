#!/usr/bin/env python3
"""The studies and the docs agree: every study of configs/studies/ names a doc that holds its
block (`<!-- generated: ID -->` ... `<!-- end generated: ID -->`) and, when it copies a figure,
the figure exists; every generated block in docs/ belongs to a study (rtsim study ID --write-doc
writes it, scripts/refresh-docs.py runs them all).

Usage: study_blocks_test.py SOURCE_DIR"""

import os
import re
import sys

src = sys.argv[1]
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


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
