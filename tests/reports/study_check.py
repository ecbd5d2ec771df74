"""What the study-table tests share: a shipped study's table rendered by `rtsim study ID
--table-only` from a run directory the test builds, the study file's table section, the files a
run writes (a CSV, a point's report.json and row.json) and the failures collected."""

import csv
import json
import os
import subprocess
import sys

import yaml

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def finish():
    for f in failures:
        print("FAIL:", f)
    sys.exit(1 if failures else 0)


def study_table(src, study):
    """configs/studies/STUDY.yaml's table section."""
    with open(os.path.join(src, "configs", "studies", study + ".yaml")) as f:
        return yaml.safe_load(f)["table"]


def render(rtsim, study, run_dir):
    """The table `rtsim study STUDY --table-only` writes from RUN_DIR ("" when it failed)."""
    r = subprocess.run(
        [rtsim, "study", study, "--out", run_dir, "--table-only"], capture_output=True, text=True
    )
    check(r.returncode == 0, f"rtsim study {study} --table-only: exit {r.returncode}: {r.stderr}")
    path = os.path.join(run_dir, "table.md")
    return open(path, newline="").read() if r.returncode == 0 else ""


def render_error(rtsim, study, run_dir, names):
    """`rtsim study STUDY --table-only` from RUN_DIR is one error, exit 2, naming each of
    `names`."""
    r = subprocess.run(
        [rtsim, "study", study, "--out", run_dir, "--table-only"], capture_output=True, text=True
    )
    check(
        r.returncode == 2 and all(n in r.stderr for n in names) and r.stderr.count("\n") == 1,
        f"{study} from {run_dir}: expected one error naming {names}: {r.returncode} {r.stderr}",
    )


def rows(table):
    """The cells of each line of a Markdown table (its header first, its rule left out)."""
    out = []
    for line in table.splitlines():
        if line.startswith("|") and not line.startswith("|---"):
            out.append(line[2:-2].split(" | "))
    return out


def expect_lines(study, table, lines):
    """Each of `lines` (worked by hand) is a line of the table."""
    have = table.splitlines()
    for line in lines:
        check(line in have, f"{study}: no line '{line}' in:\n{table}")


def write_csv(path, cols, rows_):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, cols, lineterminator="\n")
        w.writeheader()
        for r in rows_:
            w.writerow({c: "" if r.get(c) is None else r.get(c, "") for c in cols})


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
