#!/usr/bin/env python3
"""scripts/price-dram-trace.py prices a hand-written command trace as the Micron method does by
hand: each command class, the background from the cycles with a row open (worked out below from
the trace alone), their total; --compare agrees within --tolerance and flags a class beyond it;
bad input is one error line and exit 2.

Usage: price_dram_trace_test.py SOURCE_DIR"""

import json
import os
import subprocess
import sys
import tempfile
import unittest

SRC = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(__file__, "../../.."))
SCRIPT = os.path.join(SRC, "scripts", "price-dram-trace.py")

# tCK 1 ns (1000 ps: a command's cycle is time_ps / 1000), 2 channels of 2 banks, 2 devices per
# channel, a span of 20 cycles per channel, two rails.
MODEL = {
    "tck_ns": 1.0,
    "channels": 2,
    "banks": 2,
    "tRAS": 2,
    "tRC": 3,
    "tRFC": 4,
    "burst_cycles": 2,
    "devices": 2,
    "span_cycles": 20,
    "rails": [
        {"vdd": 1.0, "idd0": 10, "idd2n": 2, "idd3n": 3, "idd4r": 8, "idd4w": 6, "idd5": 7},
        {"vdd": 2.0, "idd0": 1.5, "idd2n": 0.5, "idd3n": 0.5, "idd4r": 1, "idd4w": 1, "idd5": 2},
    ],
}

# Channel 0: bank 0 open [1, 6), bank 1 open [4, 9): a row open in [1, 9) = 8 cycles; bank 0 again
# from 12, still open at the end: [12, 20) = 8 more; 16 in all. Channel 1: a PRE of a bank the
# trace never opened (closes nothing), a refresh, bank 1 open [7, 10) = 3 cycles; its PRE is listed
# before its RD at 8 (time order is not needed). C_active = 16 + 3 = 19; C_precharged = 2 x 20 -
# 19 = 21. Counts: 4 ACT, 4 PRE, 3 RD, 1 WR, 1 REF.
TRACE = """time_ps,channel,bank,command,row,column,request
1000,0,0,ACT,5,,0
2000,1,1,PRE,9,,
3000,0,0,RD,5,4,0
4000,0,1,ACT,7,,1
5000,0,1,WR,7,0,1
5000,1,0,REF,,,
6000,0,0,PRE,5,,2
7000,1,1,ACT,3,,3
10000,1,1,PRE,3,,3
8000,1,1,RD,3,8,3
9000,0,1,PRE,7,,4
12000,0,0,ACT,6,,5
14000,0,0,RD,6,1,5
"""

# Per device (x 2 devices), per command (x count), mA x V x ns = pJ:
#   rail 1 (1 V): ACT (10-3) x 2 = 14 -> 28 x 4 = 112; PRE (10-2) x (3-2) = 8 -> 16 x 4 = 64;
#     RD (8-3) x 2 = 10 -> 20 x 3 = 60; WR (6-3) x 2 = 6 -> 12 x 1 = 12; REF (7-3) x 4 = 16 -> 32;
#     background 3 x 19 + 2 x 21 = 99 -> 198.
#   rail 2 (2 V): ACT 2 x (1.5-0.5) x 2 = 4 -> 8 x 4 = 32; PRE 2 x (1.5-0.5) x 1 = 2 -> 4 x 4 =
#     16; RD 2 x (1-0.5) x 2 = 2 -> 4 x 3 = 12; WR 2 x 0.5 x 2 = 2 -> 4 x 1 = 4;
#     REF 2 x (2-0.5) x 4 = 12 -> 24; background 2 x (0.5 x 19 + 0.5 x 21) = 40 -> 80.
EXPECTED = {
    "activate": 112 + 32,
    "precharge": 64 + 16,
    "read": 60 + 12,
    "write": 12 + 4,
    "refresh": 32 + 24,
    "background": 198 + 80,
}
TOTAL = 646  # 144 + 80 + 72 + 16 + 56 + 278


class PriceDramTrace(unittest.TestCase):
    def setUp(self):
        tmp = tempfile.TemporaryDirectory(prefix="rtsim-price-dram-")
        self.addCleanup(tmp.cleanup)
        self.dir = tmp.name
        self.trace = self.write("cmds.csv", TRACE)
        self.model = self.write("model.json", json.dumps(MODEL))

    def write(self, name, text):
        path = os.path.join(self.dir, name)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        return path

    def report(self, pj):
        return self.write("report.json", json.dumps({"energy": {"dram": {"pj": pj}}}))

    def price(self, *args):
        r = subprocess.run(
            [sys.executable, SCRIPT, *args], capture_output=True, text=True, check=False
        )
        return r.returncode, r.stdout, r.stderr

    def table(self, out):
        """class -> (count, pJ) from the script's table."""
        rows = {}
        for line in out.splitlines()[1:8]:
            f = line.split()
            rows[f[0]] = (f[1] if len(f) > 2 and "." not in f[1] else "", float(f[-1]))
        return rows

    def test_prices_each_class_by_hand(self):
        code, out, err = self.price(self.trace, "--params", self.model)
        self.assertEqual(code, 0, err)
        rows = self.table(out)
        for k, pj in EXPECTED.items():
            self.assertAlmostEqual(rows[k][1], pj, places=6, msg=k)
        self.assertAlmostEqual(rows["total"][1], TOTAL, places=6)
        counts = {k: rows[k][0] for k in ["activate", "precharge", "read", "write", "refresh"]}
        self.assertEqual(
            counts, dict(activate="4", precharge="4", read="3", write="1", refresh="1")
        )
        self.assertIn("background: 19 channel-cycles active, 21 precharged", out)

    def test_reads_the_model_inside_a_report(self):
        params = self.write("run.json", json.dumps({"energy": {"dram": {"model": MODEL}}}))
        code, out, err = self.price(self.trace, "--params", params)
        self.assertEqual(code, 0, err)
        self.assertAlmostEqual(self.table(out)["total"][1], TOTAL, places=6)

    def test_compares_with_the_report(self):
        report = self.report(EXPECTED)
        code, out, err = self.price(self.trace, "--params", self.model, "--compare", report)
        self.assertEqual(code, 0, out + err)
        self.assertNotIn("DIFFERS", out)
        # Refresh 2% off (57.12 for 56): beyond 1%, within 5%; the total (+1.12 of 646) is within.
        report = self.report(dict(EXPECTED, refresh=56 * 1.02))
        code, out, _ = self.price(self.trace, "--params", self.model, "--compare", report)
        self.assertEqual(code, 1, out)
        flagged = [line.split()[0] for line in out.splitlines() if "DIFFERS" in line]
        self.assertEqual(flagged, ["refresh"])
        code, out, _ = self.price(
            self.trace, "--params", self.model, "--compare", report, "--tolerance", "5"
        )
        self.assertEqual(code, 0, out)

    def test_bad_input_is_one_line_and_exit_2(self):
        bad_header = self.write("bad.csv", TRACE.replace("time_ps", "cycle"))
        bad_row = self.write("row.csv", TRACE + "15000,0,0,NOP,,,\n")
        no_rails = self.write("m.json", json.dumps(dict(MODEL, rails=[])))
        for args, fragment in [
            ([bad_header, "--params", self.model], "header"),
            ([bad_row, "--params", self.model], "row.csv:15"),
            ([self.trace, "--params", no_rails], "rail"),
            ([self.trace, "--params", self.model, "--compare", self.model], "energy.dram.pj"),
        ]:
            code, out, err = self.price(*args)
            self.assertEqual(code, 2, args)
            self.assertEqual(err.count("\n"), 1, err)
            self.assertIn(fragment, err)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
