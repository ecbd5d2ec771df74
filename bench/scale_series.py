#!/usr/bin/env python3
"""How each stage's host cost grows with the scene (issue 52, "Scenes of millions of triangles").

    python3 bench/scale_series.py [--build build] [--scenes city-10k,city-100k,city-1m,city-4m]
        [--bvh cwbvh8] [--path] [--json FILE]

For each scene of the scale series (configs/scenes/NAME.yaml, 480x270 as the files say) it runs,
each under /usr/bin/time -v for the process's peak resident set:
- `rtsim info --json` (load, kd-tree, memory image) and `rtsim info --json --accel BVH`;
- `rtsim run --hw configs/hw/tni-paper.yaml` (the kd-tree machine; culling on, Whitted) and
  `rtsim run --hw configs/hw/bvh-tni.yaml --accel BVH`: report.json's host seconds of load,
  structure, LVB, memory image and simulation, the rays the traversal units started, and the
  memory estimate the run checked before its frame (report.json host.memory_estimate_mb);
- with --path, `rtsim render --integrator path --spp 1 --max-depth 3` (the reference tracer).
It only runs the binary and tabulates: stage seconds and peaks per scene, and each stage's
exponent k in cost = c * triangles^k, a least-squares line through (log triangles, log cost).
"""
import argparse
import json
import math
import os
import re
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SERIES = "city-10k,city-100k,city-1m,city-4m"


def timed(cmd):
    """Runs cmd under /usr/bin/time -v; returns (wall seconds, peak RSS in bytes)."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as t:
        subprocess.run(["/usr/bin/time", "-v", "-o", t.name] + cmd, cwd=ROOT, check=True)
        text = t.read()
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1))
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", text)
    parts = [float(x) for x in wall.group(1).split(":")]
    seconds = sum(v * 60 ** (len(parts) - 1 - i) for i, v in enumerate(parts))
    return seconds, rss * 1024


def info(args, scene, accel):
    with tempfile.NamedTemporaryFile("r", suffix=".json") as out:
        cmd = ["sh", "-c", '"$0" info --json --accel "$1" "$2" > "$3"']
        cmd += [os.path.join(args.build, "rtsim"), accel, scene, out.name]
        wall, rss = timed(cmd)
        j = json.load(out)
    return {"wall": wall, "rss": rss, "triangles": j["scene"]["triangles"], "info": j}


def traversal_rays(report):
    node = report["stats"]
    for part in next(u["rays"] for u in report["units"] if "rays" in u).split("."):
        node = node[part]
    return node


def run(args, scene, accel):
    hw = "configs/hw/tni-paper.yaml" if accel == "kdtree" else "configs/hw/bvh-tni.yaml"
    with tempfile.TemporaryDirectory() as out:
        cmd = [os.path.join(args.build, "rtsim"), "run", scene, "--hw", hw, "--accel", accel]
        wall, rss = timed(cmd + ["--out", out, "--no-plots", "--quiet"])
        with open(os.path.join(out, "report.json")) as f:
            r = json.load(f)
    s = r["host"]["seconds"]
    rays = traversal_rays(r)
    return {
        "wall": wall,
        "rss": rss,
        "seconds": s,
        "rays": rays,
        "per_ray_us": 1e6 * s["simulate"] / rays,
        "estimate": r["host"].get("memory_estimate_mb", 0) * 2**20,
        "cycles": r["cycles_total"],
    }


def render_path(args, scene):
    with tempfile.TemporaryDirectory() as out:
        cmd = [os.path.join(args.build, "rtsim"), "render", scene, "--integrator", "path"]
        cmd += ["--spp", "1", "--max-depth", "3", "--out", out]
        wall, rss = timed(cmd)
        with open(os.path.join(out, "render.json")) as f:
            r = json.load(f)
    rays = sum(b["rays"] + b["shadow_rays"] for b in r["path"]["bounces"])
    return {"wall": wall, "rss": rss, "seconds": r["host_seconds"], "rays": rays}


def fit(xs, ys):
    """The slope of the least-squares line through (log x, log y); None with fewer than 2."""
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y and y > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


STAGES = [  # (label, what it is read from)
    ("load s", lambda m: m["kd"]["seconds"]["load"]),
    ("kd-tree s", lambda m: m["kd"]["seconds"]["kdtree"]),
    ("BVH s", lambda m: m["bvh"]["seconds"]["kdtree"]),  # a BVH run's structure time
    ("LVB kd s", lambda m: m["kd"]["seconds"]["lvb"]),
    ("LVB BVH s", lambda m: m["bvh"]["seconds"]["lvb"]),
    ("image kd s", lambda m: m["kd"]["seconds"]["image"]),
    ("sim kd us/ray", lambda m: m["kd"]["per_ray_us"]),
    ("sim BVH us/ray", lambda m: m["bvh"]["per_ray_us"]),
    ("peak info kd MB", lambda m: m["info_kd"]["rss"] / 2**20),
    ("peak info BVH MB", lambda m: m["info_bvh"]["rss"] / 2**20),
    ("peak run kd MB", lambda m: m["kd"]["rss"] / 2**20),
    ("peak run BVH MB", lambda m: m["bvh"]["rss"] / 2**20),
    ("run kd wall s", lambda m: m["kd"]["wall"]),
    ("run BVH wall s", lambda m: m["bvh"]["wall"]),
    ("cycles kd", lambda m: m["kd"]["cycles"]),
    ("cycles BVH", lambda m: m["bvh"]["cycles"]),
]


def num(v):
    return f"{v:,.0f}" if v >= 100 else f"{v:.3g}"


def table(rows, args):
    names = [r["scene"] for r in rows]
    tris = [r["triangles"] for r in rows]
    out = ["| stage | " + " | ".join(names) + " | exponent |"]
    out.append("|---" * (len(names) + 2) + "|")
    out.append("| triangles | " + " | ".join(f"{t:,}" for t in tris) + " | |")
    for label, get in STAGES:
        label = label.replace("BVH", args.bvh)
        vals = [get(r) for r in rows]
        k = fit(tris, vals)
        cells = " | ".join(num(v) for v in vals)
        out.append(f"| {label} | {cells} | {'' if k is None else f'{k:.2f}'} |")
    if all("path" in r for r in rows):
        vals = [r["path"]["seconds"]["trace"] for r in rows]
        out.append(
            "| path 1 spp trace s | "
            + " | ".join(num(v) for v in vals)
            + f" | {fit(tris, vals):.2f} |"
        )
        vals = [r["path"]["wall"] for r in rows]
        out.append(
            "| render path wall s | "
            + " | ".join(num(v) for v in vals)
            + f" | {fit(tris, vals):.2f} |"
        )
        vals = [r["path"]["rss"] / 2**20 for r in rows]
        out.append(
            "| peak render path MB | "
            + " | ".join(num(v) for v in vals)
            + f" | {fit(tris, vals):.2f} |"
        )
    out.append("")
    out.append("| scene | machine | estimate MB | peak MB | estimate / peak |")
    out.append("|---|---|---|---|---|")
    for r in rows:
        for key, machine in (("kd", "kdtree"), ("bvh", args.bvh)):
            est, peak = r[key]["estimate"], r[key]["rss"]
            ratio = f"{est / peak:.2f}" if est else "n/a"
            est_mb = f"{est / 2**20:.0f}" if est else "n/a"
            out.append(f"| {r['scene']} | {machine} | {est_mb} | {peak / 2**20:.0f} | {ratio} |")
    return "\n".join(out)


def main():
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--build", default=os.path.join(ROOT, "build"))
    p.add_argument("--scenes", default=SERIES)
    p.add_argument("--bvh", default="cwbvh8", choices=["bvh8", "cwbvh8"])
    p.add_argument("--path", action="store_true", help="also the path-traced reference frame")
    p.add_argument("--json", help="write the measurements here")
    args = p.parse_args()
    rows = []
    for name in args.scenes.split(","):
        scene = f"configs/scenes/{name}.yaml"
        m = {"scene": name}
        m["info_kd"] = info(args, scene, "kdtree")
        m["info_bvh"] = info(args, scene, args.bvh)
        m["triangles"] = m["info_kd"]["triangles"]
        m["kd"] = run(args, scene, "kdtree")
        m["bvh"] = run(args, scene, args.bvh)
        if args.path:
            m["path"] = render_path(args, scene)
        for part in ("info_kd", "info_bvh"):
            del m[part]["info"]
        print(json.dumps(m), flush=True)
        rows.append(m)
        if args.json:
            with open(args.json, "w") as f:
                json.dump(rows, f, indent=1)
    print(table(rows, args))


if __name__ == "__main__":
    main()
