#!/usr/bin/env python3
"""Why the paper's LVB test culls so few of our leaves: Table 4 (culled leaves per light) for
variants of the robots setup, printed as the markdown tables of docs/lvb-paper.md ("What the
published leaf rates need").

    python3 scripts/lvb-study.py [--out DIR] [--rtsim build/rtsim] [--scene-root DIR]
                                 [--only a,b,c,d]

Every row is one `rtsim lvb SCENE --out DIR/runs/NAME --self-occlusion ignore --bounds B
--width 16 --height 9` (the paper's method, hierarchical walk: the same bits as the all-pairs
scan); the culled-leaf counts (Table 4) do not depend on the resolution, which only sets how many
shadow rays Table 5 traces. Variants are temporary scene files written into DIR/scenes (copies of
configs/scenes/robots.yaml with other `kdtree:` keys or lights); nothing in the repository is
changed. Runs one process at a time. Tables go to stdout and DIR/study.md; each run's lvb.json
and output stay under DIR/runs.

  a  cell vs geometry bounds, the robots setup as it is
  b  kd-tree parameters (max_depth, max_prims_per_leaf, empty_bonus)
  c  a 3 x 3 grid of light positions over the streets at three heights
  d  the robots without the city (Robot.aff without its `i 0 city2.aff` line; the other files
     are symbolic links into the scene root)
"""
import argparse
import json
import os
import re
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BASE = os.path.join(REPO, "configs", "scenes", "robots.yaml")

# The paper's Table 4 for robots (configs/paper/tables.yaml): culled leaves of 34,509.
PAPER_CULLED = [20173, 20176, 20412, 20421, 1745, 27202]
PAPER_LEAVES = 34509

# Light grid (c), read off city2.aff's building footprints: the centre lines of the three streets
# running along z, the centres of three cross streets, and three heights: 215 (our added lights'
# height: above most tower roofs, below the ceiling at y = 227.45), 100 (halfway up the street
# canyons) and 10 (street level, about the robots' height).
GRID_X = [-80, 0, 80]
GRID_Z = [-310, -160, 0]
GRID_Y = [215, 100, 10]

# Tree variants (b): (label, kdtree keys, bounds). robots.yaml's own setting is max_depth 20.
TREES = [
    ("max_depth 8", {"max_depth": 8}, "cell"),
    ("max_depth 12", {"max_depth": 12}, "cell"),
    ("max_depth 16", {"max_depth": 16}, "cell"),
    ("**max_depth 20 (robots.yaml)**", {"max_depth": 20}, "cell"),
    ("max_depth 24", {"max_depth": 24}, "cell"),
    ("max_depth 28", {"max_depth": 28}, "cell"),
    ("max_depth auto (29)", {"max_depth": 0}, "cell"),
    ("max_depth 20, max_prims_per_leaf 8", {"max_depth": 20, "max_prims_per_leaf": 8}, "cell"),
    ("max_depth 20, max_prims_per_leaf 2", {"max_depth": 20, "max_prims_per_leaf": 2}, "cell"),
    ("max_depth auto, max_prims_per_leaf 4", {"max_depth": 0, "max_prims_per_leaf": 4}, "cell"),
    ("max_depth auto, max_prims_per_leaf 1", {"max_depth": 0, "max_prims_per_leaf": 1}, "cell"),
    ("max_depth 20, empty_bonus 0", {"max_depth": 20, "empty_bonus": 0}, "cell"),
    ("max_depth 20, empty_bonus 0.5", {"max_depth": 20, "empty_bonus": 0.5}, "cell"),
    ("max_depth 20, empty_bonus 0.8", {"max_depth": 20, "empty_bonus": 0.8}, "cell"),
    ("max_depth auto, empty_bonus 0", {"max_depth": 0, "empty_bonus": 0}, "cell"),
    ("max_depth auto, empty_bonus 0.5", {"max_depth": 0, "empty_bonus": 0.5}, "cell"),
    ("max_depth 20, **geometry** bounds", {"max_depth": 20}, "geometry"),
    ("max_depth auto, **geometry** bounds", {"max_depth": 0}, "geometry"),
    (
        "max_depth 20, empty_bonus 0.8, **geometry** bounds",
        {"max_depth": 20, "empty_bonus": 0.8},
        "geometry",
    ),
]


def scene_text(kdtree=None, lights=None, geometry_file=None):
    """robots.yaml with its kdtree: line, its lights: block or its geometry file replaced."""
    text = open(BASE).read()
    if kdtree is not None:
        keys = ", ".join(f"{k}: {v}" for k, v in kdtree.items())
        text, n = re.subn(r"(?m)^kdtree:.*$", f"kdtree: {{{keys}}}", text)
        assert n == 1, "robots.yaml has no one-line kdtree: key"
    if lights is not None:
        block = "lights:\n  from_files: false\n  add:\n" + "".join(
            f"    - position: [{x}, {y}, {z}]\n" for x, y, z in lights
        )
        text, n = re.subn(r"(?m)^lights:\n(?: .*\n)*", block, text)
        assert n == 1, "robots.yaml has no lights: block"
    if geometry_file is not None:
        text, n = re.subn(r"(?m)^([ \t]*- file:).*$", rf"\1 {geometry_file}", text)
        assert n == 1
    return text


class Runner:
    def __init__(self, args):
        self.args = args
        os.makedirs(os.path.join(args.out, "scenes"), exist_ok=True)

    def lvb(self, name, text, bounds="cell"):
        scene = os.path.join(self.args.out, "scenes", name + ".yaml")
        with open(scene, "w") as f:
            f.write(text)
        out = os.path.join(self.args.out, "runs", f"{name}-{bounds}")
        cmd = [
            self.args.rtsim,
            "lvb",
            scene,
            "--out",
            out,
            "--self-occlusion",
            "ignore",
            "--bounds",
            bounds,
            "--width",
            "16",
            "--height",
            "9",
        ]
        if self.args.scene_root:
            cmd += ["--scene-root", self.args.scene_root]
        print("#", " ".join(cmd), file=sys.stderr, flush=True)
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "lvb.json")) as f:
            return json.load(f)


def pct(part, whole):
    return f"{100.0 * part / whole:.2f}%" if whole else "n/a"


def rates(j, key):
    return ", ".join(f"{100.0 * p[key]:.2f}" for p in j["per_light"])


def num(v):
    return f"{v:,}"


def study_a(r):
    runs = {b: r.lvb("robots", scene_text(), b) for b in ("cell", "geometry")}
    kd = runs["cell"]["kdtree"]
    out = [
        f"Robots as configured: {num(kd['leaves'])} leaves, {num(kd['nonempty_leaves'])} "
        "non-empty. Culled leaves per light: count, % of non-empty leaves, % of all leaves (the "
        "paper's denominator).\n",
        "| light | position | paper (of 34,509 leaves) | cell bounds | of non-empty | of all "
        "| geometry bounds | of non-empty | of all |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for i, light in enumerate(runs["cell"]["scene"]["lights"]):
        row = f"| {i + 1} | ({', '.join(f'{c:g}' for c in light['position'])}) "
        row += (
            f"| {num(PAPER_CULLED[i])} ({pct(PAPER_CULLED[i], PAPER_LEAVES)}) "
            if i < len(PAPER_CULLED)
            else "| - "
        )
        for b in ("cell", "geometry"):
            pl = runs[b]["per_light"][i]
            row += (
                f"| {num(pl['culled_leaves'])} | {pct(pl['culled_leaves'], pl['nonempty_leaves'])} "
                f"| {pct(pl['culled_leaves'], pl['leaves'])} "
            )
        out.append(row + "|")
    return out


def study_b(r):
    out = [
        "Cell bounds unless the row says otherwise. *non-empty share* = non-empty / all leaves, "
        "the highest rate of all leaves any test could reach (only non-empty leaves have an LVB). "
        "*tri/leaf* = triangle references per non-empty leaf. Rates per light 1-6, in %.\n",
        "| kd-tree | leaves (all / non-empty) | non-empty share | tri/leaf "
        "| culled, % of all leaves | culled, % of non-empty leaves |",
        "|---|---|---|---|---|---|",
    ]
    for i, (label, kd, bounds) in enumerate(TREES):
        j = r.lvb(f"tree{i:02d}", scene_text(kdtree=kd), bounds)
        k = j["kdtree"]
        out.append(
            f"| {label} | {num(k['leaves'])} / {num(k['nonempty_leaves'])} "
            f"| {pct(k['nonempty_leaves'], k['leaves'])} | {k['mean_prims_per_leaf']:.2f} "
            f"| {rates(j, 'culled_rate_all_leaves')} | {rates(j, 'culled_rate_nonempty_leaves')} |"
        )
    return out


def study_c(r):
    # One scene per height with the nine grid lights (a scene holds at most 15 lights).
    runs = {}
    for y in GRID_Y:
        lights = [(x, y, z) for z in GRID_Z for x in GRID_X]
        for b in ("cell", "geometry"):
            runs[(y, b)] = r.lvb(f"grid-y{y}", scene_text(lights=lights), b)
    kd = runs[(GRID_Y[0], "cell")]["kdtree"]
    out = [
        "Nine lights over the three streets that run along z "
        f"(x = {', '.join(map(str, GRID_X))}), at three cross streets "
        f"(z = {', '.join(map(str, GRID_Z))}), at y = {', '.join(map(str, GRID_Y))}: "
        "robots.yaml's height for its added lights (above most tower roofs, below the city's "
        "ceiling), halfway up the street canyons, and street level (about the robots' height); "
        "one scene per height, with the nine lights only. "
        f"Tree of robots.yaml ({num(kd['leaves'])} leaves, {num(kd['nonempty_leaves'])} "
        "non-empty). Each cell: culled leaves, % of all leaves (% of non-empty leaves).\n",
        "| light x, z | "
        + " | ".join(f"y = {y}, {b}" for b in ("cell", "geometry") for y in GRID_Y)
        + " |",
        "|---|" + "---|" * (2 * len(GRID_Y)),
    ]
    best = {}
    for i, (z, x) in enumerate((z, x) for z in GRID_Z for x in GRID_X):
        row = f"| {x}, {z} |"
        for b in ("cell", "geometry"):
            for y in GRID_Y:
                pl = runs[(y, b)]["per_light"][i]
                row += (
                    f" {pct(pl['culled_leaves'], pl['leaves'])} "
                    f"({pct(pl['culled_leaves'], pl['nonempty_leaves'])}) |"
                )
                best[b] = max(best.get(b, 0.0), pl["culled_rate_all_leaves"])
        out.append(row)
    out.append("")
    out.append(
        "Highest over the grid, % of all leaves: "
        + ", ".join(f"{b} bounds {100 * v:.2f}%" for b, v in best.items())
        + "."
    )
    return out


def study_d(r):
    root = (
        r.args.scene_root
        or os.environ.get("RTSIM_SCENE_ROOT")
        or os.path.join(REPO, "..", "shared", "scenes")
    )
    src = os.path.join(root, "bart", "robots")
    dst = os.path.join(r.args.out, "robots-only")
    os.makedirs(dst, exist_ok=True)
    for f in os.listdir(src):
        link = os.path.join(dst, f)
        if f != "Robot.aff" and not os.path.lexists(link):
            os.symlink(os.path.abspath(os.path.join(src, f)), link)
    with open(os.path.join(src, "Robot.aff")) as f:
        aff = "".join(line for line in f if "city2.aff" not in line)
    with open(os.path.join(dst, "Robot.aff"), "w") as f:
        f.write(aff)
    text = scene_text(geometry_file=os.path.abspath(os.path.join(dst, "Robot.aff")))
    out = [
        "The ten robots alone (same lights, same kd-tree keys). Rates per light 1-6, in %.\n",
        "| geometry | bounds | leaves (all / non-empty) | tri/leaf | culled, % of all leaves | "
        "culled, % of non-empty leaves |",
        "|---|---|---|---|---|---|",
    ]
    for b in ("cell", "geometry"):
        j = r.lvb("robots-only", text, b)
        k = j["kdtree"]
        out.append(
            f"| robots only ({num(j['scene']['triangles'])} triangles) | {b} "
            f"| {num(k['leaves'])} / {num(k['nonempty_leaves'])} | {k['mean_prims_per_leaf']:.2f} "
            f"| {rates(j, 'culled_rate_all_leaves')} | {rates(j, 'culled_rate_nonempty_leaves')} |"
        )
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument(
        "--out", default="/tmp/lvb-study", help="output directory (scenes, runs, study.md)"
    )
    ap.add_argument(
        "--rtsim", default=os.path.join(REPO, "build", "rtsim"), help="the rtsim binary"
    )
    ap.add_argument("--scene-root", default="", help="passed to rtsim lvb (default: rtsim's own)")
    ap.add_argument("--only", default="a,b,c,d", help="comma-separated parts to run (a, b, c, d)")
    args = ap.parse_args()
    r = Runner(args)
    titles = {
        "a": "a. Cell and geometry bounds",
        "b": "b. kd-trees with smaller (and larger) leaves",
        "c": "c. Lights elsewhere",
        "d": "d. The robots without the city",
    }
    parts = {"a": study_a, "b": study_b, "c": study_c, "d": study_d}
    md = []
    for p in args.only.split(","):
        md += [f"### {titles[p]}\n"] + parts[p](r) + [""]
    text = "\n".join(md)
    with open(os.path.join(args.out, "study.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
