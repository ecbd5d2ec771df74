"""What every figure module shares: matplotlib set up for files (Agg), the input checks (one
InputError per bad input, naming the file and field), atomic writes, and small drawing helpers."""

import contextlib
import csv
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)

from rtsim_plots.files import REPORT_JSON  # noqa: E402


DPI = 100
CULLED_MAX_WIDTH = 480  # panels wider than this are block-averaged: keeps culled.png small and fast
MAX_SERIES = 8  # lines per sweep plot; more are unreadable
BUSY, STALLED, IDLE = "tab:green", "tab:orange", "lightgray"


# path -> Figure of every figure saved inside figures_kept(); None outside.
_kept = None


@contextlib.contextmanager
def figures_kept():
    """Inside the block, every figure saved is also kept by its path, so a test can compare what
    it shows (axes, labels, lines, bars) with the file it was drawn from. A closed figure keeps its
    artists; the PNG files are written as ever."""
    global _kept
    outer, _kept = _kept, {}
    try:
        yield _kept
    finally:
        _kept = outer


class InputError(Exception):
    """Bad input: reported as one line and exit status 2."""


_MISSING = object()


def is_number(v):
    # bool is an int subclass in Python but never a number in our JSON.
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def field(obj, path, default=_MISSING, where=REPORT_JSON):
    """obj["a"]["b"]... for path "a.b..."; default (or an InputError) when a level is missing."""
    node = obj
    for key in path.split("."):
        if not isinstance(node, dict) or key not in node:
            if default is _MISSING:
                raise InputError(f"{where}: missing field '{path}'")
            return default
        node = node[key]
    return node


def number(obj, path, where=REPORT_JSON):
    v = field(obj, path, where=where)
    if not is_number(v):
        raise InputError(f"{where}: field '{path}' is not a number")
    return float(v)


def load_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except FileNotFoundError:
        raise InputError(f"{path}: not found") from None
    except (OSError, ValueError) as e:
        raise InputError(f"{path}: {e}") from None


def load_parsed(folder, name, parse):
    """Reads folder/name and parses it; the parser's messages name the bare file, so name the real
    one."""
    path = os.path.join(folder, name)
    try:
        return parse(load_json(path))
    except InputError as e:
        raise InputError(str(e).replace(name, path, 1)) from None


def write_atomically(path, write, written):
    """write(tmp) writes the file under a temporary name in the same directory, which then replaces
    path."""
    folder, name = os.path.split(path)
    tmp = os.path.join(folder, f".{name}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
    written.append(path)


def save(fig, path, written):
    try:
        # No Software tag: the bytes should not depend on the matplotlib version.
        write_atomically(
            path,
            lambda tmp: fig.savefig(tmp, format="png", dpi=DPI, metadata={"Software": None}),
            written,
        )
        if _kept is not None:
            _kept[path] = fig
    finally:
        plt.close(fig)


def bar_labels(ax, xs, values, fmt="{:.1f}"):
    """Value above each bar; "n/a" where the value is unknown (None)."""
    for x, v in zip(xs, values):
        if v is None:
            ax.text(x, 1, "n/a", ha="center", va="bottom", fontsize=8, color="dimgray", rotation=90)
        else:
            ax.text(x, v + 1, fmt.format(v), ha="center", va="bottom", fontsize=8)


def pct(part, whole):
    return 100.0 * part / whole if whole > 0 else None


def read_csv(folder, name):
    """Rows of folder/name as dicts of floats (None for an empty cell)."""
    path = os.path.join(folder, name)
    try:
        with open(path, encoding="utf-8", newline="") as f:
            rows = list(csv.DictReader(f))
    except FileNotFoundError:
        raise InputError(f"{path}: not found") from None
    out = []
    for i, row in enumerate(rows, start=2):
        parsed = {}
        for k, v in row.items():
            try:
                parsed[k] = float(v) if v not in ("", None) else None
            except ValueError:
                raise InputError(f"{path}:{i}: column '{k}' is not a number: {v!r}") from None
        if parsed.get("time") is None:
            raise InputError(f"{path}:{i}: missing time")
        out.append(parsed)
    return out
