#!/usr/bin/env python3
"""Prices a DRAM command trace (`rtsim run --dram-commands FILE`) by the Micron method, as
DRAMPower does, from the trace alone: an outside check of the energy rtsim reports for the same
command stream (issue 53).

    python3 scripts/price-dram-trace.py TRACE.csv --params PARAMS.json [--compare report.json]
                                        [--tolerance PCT]

TRACE.csv: time_ps,channel,bank,command,row,column,request (command ACT, PRE, RD, WR or REF).
PARAMS.json: a run's report.json (its energy.dram.model) or that object alone:
    {"tck_ns": 0.625, "channels": 8, "banks": 8, "tRAS": 68, "tRC": 95, "tRFC": 288,
     "burst_cycles": 8, "devices": 1, "span_cycles": 127329,
     "rails": [{"vdd": 1.1, "idd0": 45, "idd2n": 27, "idd3n": 30, "idd4r": 275, "idd4w": 210,
                "idd5": 90}]}
Timings in command cycles of tck_ns, currents in mA, volts; span_cycles is the frame's length in
command cycles from the trace's time 0. Per device, times `devices`, summed over the rails
(mA x V x ns = pJ):
    ACT  VDD (IDD0 - IDD3N) tRAS tCK            PRE  VDD (IDD0 - IDD2N) (tRC - tRAS) tCK
    RD   VDD (IDD4R - IDD3N) burst_cycles tCK    WR   VDD (IDD4W - IDD3N) burst_cycles tCK
    REF  VDD (IDD5 - IDD3N) tRFC tCK
    background  VDD tCK (IDD3N C_active + IDD2N C_precharged)
C_active: the cycles, summed over channels, in which a channel has a row open in some bank (a bank
opens at its ACT's cycle and closes at its PRE's; a PRE of a bank the trace never opened closes
nothing; a bank open at the end stays open until span_cycles); C_precharged = channels x
span_cycles - C_active. Prints the count and energy of each class and the total, in pJ. With
--compare, also report.json's energy.dram.pj (activate, precharge, read, write, refresh,
background) and the difference; exits 1 if a class or the total differs by more than --tolerance
percent (default 1), 2 on bad input.
"""
import argparse
import csv
import json
import sys
from array import array

HEADER = ["time_ps", "channel", "bank", "command", "row", "column", "request"]
CLASSES = ["activate", "precharge", "read", "write", "refresh", "background"]
COMMANDS = {"ACT": "activate", "PRE": "precharge", "RD": "read", "WR": "write", "REF": "refresh"}
TIMINGS = ["tck_ns", "channels", "banks", "tRAS", "tRC", "tRFC", "burst_cycles", "devices"]
CURRENTS = ["vdd", "idd0", "idd2n", "idd3n", "idd4r", "idd4w", "idd5"]
BANK_BITS = 20  # an ACT or PRE as one integer: cycle << BANK_BITS | bank << 1 | (1 if ACT)


class InputError(Exception):
    pass


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        raise InputError(f"{path}: {e}")


def load_model(path):
    """The device's parameters: report.json's energy.dram.model, or the file itself."""
    j = load_json(path)
    if isinstance(j, dict) and "energy" in j:
        j = (j["energy"] or {}).get("dram", {}).get("model")
        if j is None:
            raise InputError(f"{path}: no energy.dram.model")
    if not isinstance(j, dict):
        raise InputError(f"{path}: expected an object")
    for key in TIMINGS + ["span_cycles", "rails"]:
        if key not in j:
            raise InputError(f"{path}: the model lacks '{key}'")
    if not j["rails"] or any(k not in r for r in j["rails"] for k in CURRENTS):
        raise InputError(f"{path}: each rail needs {', '.join(CURRENTS)}")
    if j["tck_ns"] <= 0 or j["channels"] < 1 or not 1 <= j["banks"] < 1 << (BANK_BITS - 1):
        raise InputError(f"{path}: tck_ns, channels or banks out of range")
    return j


def read_trace(path, model):
    """The commands by class, and each channel's ACTs and PREs (array of encoded integers)."""
    tck_ps = model["tck_ns"] * 1000.0
    counts = dict.fromkeys(COMMANDS.values(), 0)
    events = [array("q") for _ in range(model["channels"])]
    try:
        with open(path, newline="") as f:
            rows = csv.reader(f)
            if next(rows, None) != HEADER:
                raise InputError(f"{path}: expected the header {','.join(HEADER)}")
            for n, row in enumerate(rows, start=2):
                try:
                    kind = COMMANDS[row[3]]
                    channel, bank = int(row[1]), int(row[2])
                    cycle = round(int(row[0]) / tck_ps)
                    if not (0 <= channel < model["channels"] and 0 <= bank < model["banks"]):
                        raise ValueError("channel or bank out of range")
                except (IndexError, KeyError, ValueError) as e:
                    raise InputError(f"{path}:{n}: not a command row ({e}): {','.join(row)}")
                counts[kind] += 1
                if kind in ("activate", "precharge"):
                    act = 1 if kind == "activate" else 0
                    events[channel].append(cycle << BANK_BITS | bank << 1 | act)
    except OSError as e:
        raise InputError(f"{path}: {e}")
    return counts, events


def active_cycles(channel_events, banks, span):
    """The cycles of one channel with a row open in some bank, up to `span` for a bank left open."""
    is_open = bytearray(banks)
    opened, since, total = 0, 0, 0
    for e in sorted(channel_events):
        cycle, bank, act = e >> BANK_BITS, (e >> 1) & ((1 << (BANK_BITS - 1)) - 1), e & 1
        if act and not is_open[bank]:
            is_open[bank] = 1
            opened += 1
            if opened == 1:
                since = cycle
        elif not act and is_open[bank]:
            is_open[bank] = 0
            opened -= 1
            if opened == 0:
                total += cycle - since
    if opened > 0 and span > since:
        total += span - since
    return total


def price(model, counts, c_active):
    """Energy in pJ by class (CLASSES) for the counts and the active cycles."""
    tck, burst, dev = model["tck_ns"], model["burst_cycles"], model["devices"]
    c_precharged = model["channels"] * model["span_cycles"] - c_active
    energy = dict.fromkeys(CLASSES, 0.0)
    for r in model["rails"]:
        v, idd3n = r["vdd"], r["idd3n"]
        per_command = {
            "activate": v * (r["idd0"] - idd3n) * model["tRAS"] * tck,
            "precharge": v * (r["idd0"] - r["idd2n"]) * (model["tRC"] - model["tRAS"]) * tck,
            "read": v * (r["idd4r"] - idd3n) * burst * tck,
            "write": v * (r["idd4w"] - idd3n) * burst * tck,
            "refresh": v * (r["idd5"] - idd3n) * model["tRFC"] * tck,
        }
        for k, e in per_command.items():
            energy[k] += dev * e * counts[k]
        energy["background"] += dev * v * tck * (idd3n * c_active + r["idd2n"] * c_precharged)
    return energy, c_precharged


def reported(path):
    """report.json's energy.dram.pj by class, with its total."""
    pj = (load_json(path).get("energy") or {}).get("dram", {}).get("pj")
    if not isinstance(pj, dict) or any(k not in pj for k in CLASSES):
        raise InputError(f"{path}: energy.dram.pj lacks one of {', '.join(CLASSES)}")
    out = {k: float(pj[k]) for k in CLASSES}
    out["total"] = float(pj.get("total", sum(out.values())))
    return out


def differs(ours, theirs, tolerance_pct):
    if theirs == 0:
        return ours != 0
    return abs(ours - theirs) > tolerance_pct / 100.0 * abs(theirs)


def table(counts, energy, report, tolerance):
    """The table's lines, and whether any figure differs from the report's."""
    head = f"{'class':<11} {'count':>12} {'energy_pj':>16}"
    if report:
        head += f" {'report_pj':>16} {'diff_pct':>9}"
    lines, bad = [head], False
    for k in CLASSES + ["total"]:
        line = f"{k:<11} {counts.get(k, ''):>12} {energy[k]:>16.3f}"
        if report:
            diff = 100.0 * (energy[k] - report[k]) / report[k] if report[k] else 0.0
            wrong = differs(energy[k], report[k], tolerance)
            bad |= wrong
            line += f" {report[k]:>16.3f} {diff:>+9.3f}" + ("  DIFFERS" if wrong else "")
        lines.append(line)
    return lines, bad


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("trace", help="the CSV of rtsim run --dram-commands")
    p.add_argument("--params", required=True, help="report.json, or its energy.dram.model alone")
    p.add_argument("--compare", help="report.json whose energy.dram.pj to compare with")
    p.add_argument("--tolerance", type=float, default=1.0, help="percent (default 1)")
    a = p.parse_args(argv)
    try:
        model = load_model(a.params)
        counts, events = read_trace(a.trace, model)
        report = reported(a.compare) if a.compare else None
    except InputError as e:
        print(f"price-dram-trace: error: {e}", file=sys.stderr)
        return 2
    span = model["span_cycles"]
    c_active = sum(active_cycles(ev, model["banks"], span) for ev in events)
    energy, c_precharged = price(model, counts, c_active)
    energy["total"] = sum(energy[k] for k in CLASSES)
    lines, bad = table(counts, energy, report, a.tolerance)
    print("\n".join(lines))
    print(f"background: {c_active} channel-cycles active, {c_precharged} precharged")
    if report:
        print(f"{'differs' if bad else 'agrees'} within {a.tolerance:g}%: {a.compare}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
