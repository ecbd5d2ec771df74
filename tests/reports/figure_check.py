"""What the figure tests (tests/reports/*_figures_test.py) share: the figure modules imported from
the source tree, a plots.py mode run on a folder of input files with its figures kept, and what an
Axes shows read back from matplotlib (bars, lines, labels), to compare with those input files.

A test: python3 tests/reports/NAME_figures_test.py SOURCE_DIR (the matplotlib of the Python that
rtsim runs plots.py with: /usr/bin/python3 on Debian)."""

import csv
import importlib
import json
import math
import os
import sys
import tempfile
import unittest

SRC = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(__file__, "../../.."))
sys.path.insert(0, os.path.join(SRC, "reports"))
common = importlib.import_module("rtsim_plots.common")
BarContainer = importlib.import_module("matplotlib.container").BarContainer


def module(name):
    """reports/rtsim_plots/NAME.py of the source tree."""
    return importlib.import_module(f"rtsim_plots.{name}")


def main():
    unittest.main(argv=sys.argv[:1], verbosity=2)


def bars(ax):
    """The bar containers of ax (one per ax.bar or ax.barh call, in drawing order)."""
    return list(ax.containers)


def error_bars(container):
    """The lower and upper ends of the vertical error bars of an ErrorbarContainer (ax.errorbar, or
    a bar container's .errorbar), in drawing order."""
    _, _, (bars, *_) = container.lines
    segments = bars.get_segments()
    return [float(s[0][1]) for s in segments], [float(s[1][1]) for s in segments]


def heights(container):
    return [p.get_height() for p in container.patches]


def series(ax):
    """label -> (xdata, ydata) of the labelled lines (matplotlib names its helper lines '_...')."""
    return {
        line.get_label(): (
            [float(x) for x in line.get_xdata()],
            [float(y) for y in line.get_ydata()],
        )
        for line in ax.get_lines()
        if not line.get_label().startswith("_")
    }


def xticks(ax):
    return [t.get_text() for t in ax.get_xticklabels()]


def yticks(ax):
    return [t.get_text() for t in ax.get_yticklabels()]


def texts(artist):
    """The texts drawn in an Axes (value labels, n/a, notes; annotations included) or a figure
    (its suptitle)."""
    return [t.get_text() for t in artist.texts]


def legend(artist):
    """label -> RGBA face colour of the patches in the legend of an Axes, or the legends of a
    figure or subfigure."""
    out = {}
    for leg in artist.legends if hasattr(artist, "legends") else [artist.get_legend()]:
        # legendHandles before matplotlib 3.7 (Debian 12 has 3.6), legend_handles since.
        handles = getattr(leg, "legend_handles", None) or leg.legendHandles
        out.update(
            (t.get_text(), tuple(h.get_facecolor())) for t, h in zip(leg.get_texts(), handles)
        )
    return out


def same(a, b, rel=1e-9):
    """Numbers equal to rounding (NaN equals NaN: a gap in the data is a gap in the line)."""
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return math.isclose(a, b, rel_tol=rel, abs_tol=1e-12)


class FigureTest(unittest.TestCase):
    """A temporary folder for the input files, and a plots.py mode run on it."""

    def setUp(self):
        tmp = tempfile.TemporaryDirectory(prefix="rtsim-figures-")
        self.addCleanup(tmp.cleanup)
        self.dir = tmp.name

    def write_json(self, name, obj):
        with open(os.path.join(self.dir, name), "w", encoding="utf-8") as f:
            json.dump(obj, f)

    def write_csv(self, name, header, rows):
        """rows of dicts; a missing or None value is an empty cell, as the commands write it."""
        with open(os.path.join(self.dir, name), "w", encoding="utf-8", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(header)
            for row in rows:
                w.writerow(["" if row.get(k) is None else row[k] for k in header])

    def draw(self, mode):
        """Runs mode (run, sweep, ...) on the folder; its figures by path relative to the folder."""
        written = []
        with common.figures_kept() as kept:
            mode(self.dir, written)
        for path in kept:
            self.assertIn(path, written)
            with open(path, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n", path)
        return {os.path.relpath(path, self.dir): fig for path, fig in kept.items()}

    def assertNoMarkdown(self):
        """The C++ side writes every Markdown report: no .md file in the folder (or plots/)."""
        found = [
            os.path.relpath(os.path.join(root, f), self.dir)
            for root, _, files in os.walk(self.dir)
            for f in files
            if f.endswith(".md")
        ]
        self.assertEqual(found, [], "Markdown written by Python")

    def assertNumbers(self, actual, expected, msg=None):
        """Two sequences of numbers equal to rounding, element by element."""
        actual, expected = list(actual), list(expected)
        self.assertEqual(len(actual), len(expected), f"{msg}: {actual} against {expected}")
        for i, (a, e) in enumerate(zip(actual, expected)):
            self.assertTrue(same(float(a), float(e)), f"{msg}[{i}]: {a} != {e} ({actual})")
