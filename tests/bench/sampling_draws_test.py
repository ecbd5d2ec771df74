#!/usr/bin/env python3
"""bench_sampling_draws is the binary's estimator: on a sampled run's own batches, at its settings
and seed, it gives the run's report.json estimates and intervals; on a full run at a fraction of 1
every unit is measured and the estimate is the truth, with no interval; on a full run the truth
is the run's cycles per phase; bench/sampling_plan_study.py tabulates its draws, and
bench/sampling_regression.py reads bench_sampling_features' columns (by stage) beside the run's
batches.

Usage: sampling_draws_test.py SOURCE_DIR RTSIM_BINARY BENCH_DIR"""

import csv
import io
import json
import os
import subprocess
import sys
import tempfile

src, rtsim, bench = sys.argv[1], sys.argv[2], sys.argv[3]
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def run(*args, **kw):
    r = subprocess.run(list(args), capture_output=True, text=True, cwd=src, **kw)
    check(r.returncode == 0, f"{' '.join(args)}: exit {r.returncode}: {r.stderr}")
    return r.stdout


def draws(run_dir, pass_file, *opts):
    out = run(
        os.path.join(bench, "bench_sampling_draws"),
        "--config",
        os.path.join(run_dir, "config.json"),
        "--pass",
        pass_file,
        *opts,
    )
    return {(r["seed"], r["phase"]): r for r in csv.DictReader(io.StringIO(out))}


with tempfile.TemporaryDirectory() as tmp:
    city = ["configs/scenes/city.yaml", "--hw", "configs/hw/tni-paper.yaml"]
    city += ["--width", "256", "--height", "144", "--no-plots", "--quiet"]
    full, sampled = os.path.join(tmp, "full"), os.path.join(tmp, "s3")
    run(rtsim, "run", *city, "--out", full)
    sample = ["--sample", "0.1", "--set", "run.sample_unit=256", "--set", "run.sample_seed=3"]
    run(rtsim, "run", *city, *sample, "--out", sampled)
    pass_file = os.path.join(tmp, "pass.bin")
    run(
        os.path.join(bench, "bench_sampling_features"),
        "--config",
        os.path.join(full, "config.json"),
        "--out",
        os.path.join(tmp, "features.csv"),
        "--pass",
        pass_file,
        "--steps-stride",
        "4",
    )
    # The sampled run's own estimates, from its windows' batches (the pass is the full run's:
    # it depends on no sample setting).
    report = json.load(open(os.path.join(sampled, "report.json")))
    opts = ["--fraction", "0.1", "--unit", "256", "--first-seed", "3", "--seeds", "1"]
    got = draws(sampled, pass_file, *opts)
    for phase, key in (("primary", "primary"), ("shadow", "shadow"), ("frame", "total")):
        r = got.get(("3", phase), {})
        check(
            r.get("truth") == "" and float(r.get("ci95", "nan")) == report[f"cycles_{key}_ci95"],
            f"{phase}: interval {r.get('ci95')} against the run's {report[f'cycles_{key}_ci95']}",
        )
        # The report's frame is the sum of its phases, each rounded.
        check(
            abs(float(r.get("estimate", "nan")) - report[f"cycles_{key}"])
            <= (1 if key == "total" else 0.5),
            f"{phase}: estimate {r.get('estimate')} against the run's {report[f'cycles_{key}']}",
        )
    # A full run: every unit measured at a fraction of 1; the truth its cycles at any fraction.
    report = json.load(open(os.path.join(full, "report.json")))
    whole = draws(full, pass_file, "--fraction", "1", "--unit", "256", "--seeds", "1")
    some = draws(full, pass_file, "--fraction", "0.25", "--unit", "256", "--seeds", "4")
    for phase, key in (("primary", "primary"), ("shadow", "shadow"), ("frame", "total")):
        r = whole.get(("1", phase), {})
        check(
            r.get("truth") == r.get("estimate") and float(r.get("ci95", "nan")) == 0,
            f"{phase} at a fraction of 1: {r}",
        )
        for seed in "1234":
            t = some.get((seed, phase), {}).get("truth", "nan")
            check(float(t) == report[f"cycles_{key}"], f"{phase}, seed {seed}: truth {t}")
    table = run(
        sys.executable,
        os.path.join(src, "bench", "sampling_plan_study.py"),
        full,
        "--units",
        "256",
        "--fractions",
        "0.25",
        "--strata",
        "neyman",
        "--seeds",
        "4",
        "--build",
        os.path.dirname(bench),
    )
    lines = [x for x in table.splitlines() if x.startswith("| full | neyman | 0.25 | 256 |")]
    check(len(lines) == 3 and all(x.endswith(" of 4 |") for x in lines), f"the study:\n{table}")
    # The features' R^2 per phase: a row per feature, the traversal stage's reads among them.
    fits = run(
        sys.executable,
        os.path.join(src, "bench", "sampling_regression.py"),
        full + ":" + os.path.join(tmp, "features.csv"),
        "--units",
        "8",
    )
    for phase in ("primary", "shadow", "frame"):
        check(f"\n# full, {phase}: " in fits, f"sampling_regression.py: no {phase}:\n{fits}")
    rows = [
        x.split(" | ") for x in fits.splitlines() if x.startswith("| 8 x 64 | traversal_reads |")
    ]
    check(
        len(rows) == 3 and all(0 <= float(r[2]) <= 1 for r in rows),
        f"sampling_regression.py: traversal_reads rows {rows}",
    )

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
