#!/usr/bin/env python3
"""A mutation fuzzer of rtsim's readers (issue 22): seeds of every input kind (AFF, PLY ascii and
binary, OBJ+MTL, glTF and GLB, scene/hardware/sweep YAML, --set values, a run's config.json,
command-line values), mutated (bytes
flipped, cut, repeated, numbers swapped for extreme ones, bytes that are not UTF-8), each run
through the command that reads it, under a time and an address-space limit. A case passes when
rtsim exits 0, or exits 2 with exactly one `rtsim: error:` line on stderr; anything else (exit 1,
a signal, a timeout, several lines) is a finding, kept with its input under OUT/findings/.

    python3 tests/fuzz/fuzz.py --rtsim build/rtsim --cases 400 --seed 1 [--out DIR]
        [--kinds aff,ply]

Deterministic for a seed. Exit status 1 if there is a finding.
"""
import argparse
import os
import random
import re
import resource
import shutil
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

AFF = b"""v
from 0 0 5
at 0 0 0
up 0 1 0
angle 40
hither 0.01
resolution 16 9
l 1 4 2 1 1 1
la box 0 3 0 1 1 1
f 0.8 0.7 0.6 0.5 0.3 8 0 1
m vertices 4  -1 -1 0  1 -1 0  1 1 0  -1 1 0
triangles 2  0 1 2  0 2 3
p 3 -2 -2 -1  2 -2 -1  0 2 -1
pp 3 -2 -2 -2 0 0 1  2 -2 -2 0 0 1  0 2 -2 0 0 1
tpa 2  0  0 0 -3 0 0 1  1 0 -3 0 0 1  0 1 -3 0 0 1  1  0 0 -3 0 0 1  1 0 -3 0 0 1  0 1 -3 0 0 1
a 0 1 10
x box {
m vertices 3  0 0 -4  1 0 -4  0 1 -4  triangles 1  0 1 2
}
k box {
transl 4  0 0 0 0 0 0 0  0 0 0 0 0 0 0  1 1 0 0 0 0 0  2 1 0 0 0 0 0
rot 4  0 0 1 0 0 0 0 0  0 0 1 0 0 0 0 0  1 0 1 0 90 0 0 0  2 0 1 0 90 0 0 0
visibility 2 0 1 1 0
}
"""

PLY_ASCII = b"""ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 2
property list uchar int vertex_indices
end_header
-1 -1 -3
1 -1 -3
1 1 -3
-1 1 -3
3 0 1 2
3 0 2 3
"""


def ply_binary():
    head = (
        b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
        b"property float y\nproperty float z\nelement face 1\n"
        b"property list uchar int vertex_indices\nend_header\n"
    )
    body = struct.pack("<9f", -1, -1, -3, 1, -1, -3, 0, 1, -3) + struct.pack("<B3i", 3, 0, 1, 2)
    return head + body


def gltf():
    """One triangle: float positions and 16-bit indices in a data: URI buffer."""
    import base64
    import json

    data = struct.pack("<9f", -1, -1, -3, 1, -1, -3, 0, 1, -3) + struct.pack("<3H", 0, 1, 2)
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [
            {
                "byteLength": len(data),
                "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode(),
            }
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 6},
        ],
        "accessors": [
            {
                "bufferView": 0,
                "componentType": 5126,
                "count": 3,
                "type": "VEC3",
                "min": [-1, -1, -3],
                "max": [1, 1, -3],
            },
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0, "translation": [0, 0, 0]}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }
    return json.dumps(doc, indent=1).encode()


def glb():
    """The same triangle as a binary glTF: a JSON chunk and a BIN chunk."""
    import json

    data = struct.pack("<9f", -1, -1, -3, 1, -1, -3, 0, 1, -3) + struct.pack("<3H", 0, 1, 2)
    doc = json.loads(gltf())
    doc["buffers"] = [{"byteLength": len(data)}]
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    data += b"\0" * (-len(data) % 4)
    chunks = (
        struct.pack("<I4s", len(text), b"JSON")
        + text
        + struct.pack("<I4s", len(data), b"BIN\0")
        + data
    )
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


OBJ = b"""mtllib m.mtl
v -1 -1 -3
v 1 -1 -3
v 1 1 -3
v -1 1 -3
vn 0 0 1
usemtl red
f 1//1 2//1 3//1
f 1 3 4
"""
MTL = b"newmtl red\nKd 0.8 0.1 0.1\nKs 0.2 0.2 0.2\nNs 10\n"

SCENE = b"""name: fuzz
geometry:
  - triangles:
      vertices: [[-1, -1, -3], [1, -1, -3], [0, 1, -3], [-4, -2, -6], [4, -2, -6], [0, -2, 0]]
      indices: [[0, 1, 2], [3, 4, 5]]
      material: {diffuse: [0.8, 0.7, 0.6], reflectance: 0.2}
resolution: [16, 9]
camera: {eye: [0, 0, 2], dir: [0, 0, -1], up: [0, 1, 0], vfov_deg: 45}
lights:
  add:
    - position: [1, 3, 1]
    - area: {corner: [0, 3, -2], edge1: [0.5, 0, 0], edge2: [0, 0, 0.5], two_sided: true}
      samples: 4
kdtree: {max_depth: 12}
"""

SWEEP = b"""name: fuzz
scenes: [SCENE]
hw: HW
set: {run.width: 8, run.height: 8}
axes:
  hw.trv.l1.size_kb: [4, 8]
  run.lvb: [on, off]
metrics: [cycles_total, trv_l1_hit_rate]
"""

EXTREMES = [
    b"0",
    b"-1",
    b"4294967295",
    b"18446744073709551616",
    b"1e308",
    b"-1e308",
    b"nan",
    b"inf",
    b"99999999999",
    b"2147483648",
    b"0.0000001",
    b"3",
]


def mutate(data, rng):
    if MUTATIONS == 0:
        return data
    data = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        kind = rng.randrange(6)
        if not data:
            data += b"x"
        at = rng.randrange(len(data))
        if kind == 0:  # a number swapped for an extreme one
            nums = [m for m in re.finditer(rb"-?\d+(\.\d+)?", bytes(data))]
            if nums:
                m = rng.choice(nums)
                data[m.start() : m.end()] = rng.choice(EXTREMES)
        elif kind == 1:
            data[at] = rng.randrange(256)
        elif kind == 2:
            del data[at : at + rng.randint(1, 16)]
        elif kind == 3:
            end = min(len(data), at + rng.randint(1, 32))
            data[at:at] = data[at:end] * rng.randint(1, 3)
        elif kind == 4:  # not UTF-8
            data[at:at] = bytes([rng.choice([0xC3, 0xDB, 0xFF, 0x80, 0xE2])])
        else:
            data = data[:at]
    return bytes(data)


AS_LIMIT = 4 << 30  # bytes of address space a case may map; 0: none (AddressSanitizer's shadow)


def limits():
    if AS_LIMIT:
        resource.setrlimit(resource.RLIMIT_AS, (AS_LIMIT, AS_LIMIT))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))


def run(cmd, cwd, timeout):
    try:
        p = subprocess.run(cmd, cwd=cwd, capture_output=True, timeout=timeout, preexec_fn=limits)
    except subprocess.TimeoutExpired:
        return None, b"", b"timeout"
    return p.returncode, p.stdout, p.stderr


def verdict(code, err):
    if code is None:
        return "timeout"
    if code == 0:
        return None
    lines = [line for line in err.decode("utf-8", "replace").splitlines() if line.strip()]
    errors = [line for line in lines if line.startswith("rtsim: error:")]
    if code == 2 and len(errors) == 1:
        return None
    return f"exit {code}" if code != 2 else f"exit 2 with {len(errors)} error lines"


def scene_for(geom):
    """A scene of the one geometry file `geom`, at 16x9."""
    return (
        b"geometry:\n  - file: "
        + geom.encode()
        + b"\nresolution: [16, 9]\ncamera: {eye: [0, 0, 2], dir: [0, 0, -1], "
        b"up: [0, 1, 0], vfov_deg: 45}\nlights:\n  add:\n    - position: [1, 3, 1]\n"
    )


def geometry_case(kind, rng, work, rtsim):
    """A mutated geometry file of `kind` under a scene that loads it; None for another kind."""
    if kind == "aff":
        open(os.path.join(work, "s.aff"), "wb").write(mutate(AFF, rng))
        open(os.path.join(work, "scene.yaml"), "wb").write(scene_for("s.aff"))
        return [rtsim, "info", "scene.yaml", "--scene-root", work]
    if kind in ("ply", "plyb"):
        open(os.path.join(work, "s.ply"), "wb").write(
            mutate(PLY_ASCII if kind == "ply" else ply_binary(), rng)
        )
        open(os.path.join(work, "scene.yaml"), "wb").write(scene_for("s.ply"))
        return [rtsim, "info", "scene.yaml", "--scene-root", work]
    if kind == "gltf":
        open(os.path.join(work, "s.gltf"), "wb").write(mutate(gltf(), rng))
        open(os.path.join(work, "scene.yaml"), "wb").write(scene_for("s.gltf"))
        return [rtsim, "info", "scene.yaml", "--scene-root", work]
    if kind == "glb":
        open(os.path.join(work, "s.glb"), "wb").write(mutate(glb(), rng))
        open(os.path.join(work, "scene.yaml"), "wb").write(scene_for("s.glb"))
        return [rtsim, "info", "scene.yaml", "--scene-root", work]
    if kind == "obj":
        open(os.path.join(work, "s.obj"), "wb").write(mutate(OBJ, rng))
        open(os.path.join(work, "m.mtl"), "wb").write(
            mutate(MTL, rng) if rng.random() < 0.5 else MTL
        )
        open(os.path.join(work, "scene.yaml"), "wb").write(scene_for("s.obj"))
        return [rtsim, "info", "scene.yaml", "--scene-root", work]
    return None


def args_case(rng, work, rtsim, small_hw):
    """A mutated value of one command-line option that takes a value."""
    open(os.path.join(work, "scene.yaml"), "wb").write(SCENE)
    options = [
        ["run", "scene.yaml", "--hw", small_hw, "--no-plots", "--quiet", "--out", "o", "--width"],
        [
            "run",
            "scene.yaml",
            "--hw",
            small_hw,
            "--no-plots",
            "--quiet",
            "--out",
            "o",
            "--reflections",
        ],
        ["run", "scene.yaml", "--hw", small_hw, "--no-plots", "--quiet", "--out", "o", "--lvb"],
        ["render", "scene.yaml", "--out", "o", "--threads"],
        ["lvb", "scene.yaml", "--out", "o", "--lvb-threads"],
        ["sweep", "sweep.yaml", "--out", "o", "--jobs"],
        ["sweep", "sweep.yaml", "--out", "o", "--point-timeout"],
        ["animate", "scene.yaml", "--hw", small_hw, "--out", "o", "--times"],
    ]
    # One point: the values under test are the command line's, not the sweep's work
    text = SWEEP.replace(b"SCENE", b"scene.yaml").replace(b"HW", small_hw.encode())
    text = text.replace(b"  hw.trv.l1.size_kb: [4, 8]\n", b"").replace(b"[on, off]", b"[on]")
    open(os.path.join(work, "sweep.yaml"), "wb").write(text)
    i = rng.randrange(len(options))
    seed_value = [b"8", b"1", b"on", b"2", b"2", b"1", b"60", b"0:1:1"][i]
    return [rtsim] + options[i] + [mutate(seed_value, rng).replace(b"\0", b"")]  # argv: no NUL


def case(kind, rng, work, rtsim):
    """Writes one mutated input of `kind` into `work` and returns the command that reads it."""
    small_hw = os.path.join(ROOT, "configs/hw/small.yaml")
    cmd = geometry_case(kind, rng, work, rtsim)
    if cmd is not None:
        return cmd
    if kind == "config":
        # A run's config.json (made once from SCENE by make_config), to repeat with --config
        open(os.path.join(work, "scene.yaml"), "wb").write(SCENE)  # the scene it names
        open(os.path.join(work, "config.json"), "wb").write(mutate(CONFIG, rng))
        return [rtsim, "run", "--config", "config.json", "--out", "o", "--no-plots", "--quiet"]
    if kind == "args":
        return args_case(rng, work, rtsim, small_hw)
    if kind == "scene":
        open(os.path.join(work, "scene.yaml"), "wb").write(mutate(SCENE, rng))
        return [rtsim, "run", "scene.yaml", "--hw", small_hw, "--out", "o", "--no-plots", "--quiet"]
    if kind == "hw":
        open(os.path.join(work, "scene.yaml"), "wb").write(SCENE)
        open(os.path.join(work, "hw.yaml"), "wb").write(mutate(open(small_hw, "rb").read(), rng))
        return [
            rtsim,
            "run",
            "scene.yaml",
            "--hw",
            "hw.yaml",
            "--out",
            "o",
            "--no-plots",
            "--quiet",
        ]
    if kind == "sweep":
        open(os.path.join(work, "scene.yaml"), "wb").write(SCENE)
        text = SWEEP.replace(b"SCENE", b"scene.yaml").replace(b"HW", small_hw.encode())
        open(os.path.join(work, "sweep.yaml"), "wb").write(mutate(text, rng))
        return [rtsim, "sweep", "sweep.yaml", "--emit", "slurm", "--out", "o"]
    if kind == "set":
        open(os.path.join(work, "scene.yaml"), "wb").write(SCENE)
        value = mutate(
            rng.choice(
                [
                    b"run.width=8",
                    b"hw.trv.count=2",
                    b"scene.resolution=[8, 8]",
                    b"run.lvb=on",
                    b"hw.dram.channels=4",
                ]
            ),
            rng,
        )
        return [
            rtsim,
            "run",
            "scene.yaml",
            "--hw",
            small_hw,
            "--set",
            value.replace(b"\0", b""),
            "--out",
            "o",
            "--no-plots",
            "--quiet",
        ]
    raise ValueError(kind)


MUTATIONS = 1  # 0: the seeds as they are (a check of the seeds)
KINDS = [
    "aff",
    "ply",
    "plyb",
    "obj",
    "gltf",
    "glb",
    "scene",
    "hw",
    "sweep",
    "set",
    "config",
    "args",
]
CONFIG = b""  # a run's config.json


def make_config(rtsim, where):
    """config.json of a tiny run of SCENE in `where` (kept for the cases: it names the scene)."""
    open(os.path.join(where, "scene.yaml"), "wb").write(SCENE)
    code, _, err = run(
        [
            rtsim,
            "run",
            "scene.yaml",
            "--hw",
            os.path.join(ROOT, "configs/hw/small.yaml"),
            "--width",
            "8",
            "--height",
            "8",
            "--out",
            "o",
            "--no-plots",
            "--quiet",
        ],
        where,
        60,
    )
    if code != 0:
        sys.exit(f"fuzz: the run that makes config.json failed: {err.decode('utf-8', 'replace')}")
    return open(os.path.join(where, "o", "config.json"), "rb").read()


def main():
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--rtsim", default=os.path.join(ROOT, "build/rtsim"))
    ap.add_argument("--cases", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--kinds", default=",".join(KINDS))
    ap.add_argument("--timeout", type=float, default=30)
    ap.add_argument(
        "--out", default=None, help="where findings go (default: a temporary directory)"
    )
    ap.add_argument(
        "--no-as-limit",
        action="store_true",
        help="no address-space limit (a sanitizer build reserves terabytes of it)",
    )
    args = ap.parse_args()
    global AS_LIMIT
    if args.no_as_limit:
        AS_LIMIT = 0
    rng = random.Random(args.seed)
    kinds = args.kinds.split(",")
    out = args.out or tempfile.mkdtemp(prefix="rtsim-fuzz-")
    findings = 0
    rtsim = os.path.abspath(args.rtsim)
    global CONFIG  # noqa: PLW0603
    config_dir = tempfile.mkdtemp(prefix="config-")
    CONFIG = make_config(rtsim, config_dir)
    # Every seed as it is must run: else its mutations test only the first error.
    global MUTATIONS  # noqa: PLW0603
    MUTATIONS = 0
    for kind in kinds:
        work = tempfile.mkdtemp(prefix="seed-")
        code, _, err = run(case(kind, rng, work, rtsim), work, args.timeout)
        shutil.rmtree(work, ignore_errors=True)
        if code != 0:
            print(f"fuzz: the {kind} seed does not run: {err.decode('utf-8', 'replace').strip()}")
            return 1
    MUTATIONS = 1
    for n in range(args.cases):
        kind = kinds[n % len(kinds)]
        work = tempfile.mkdtemp(prefix="case-")
        try:
            cmd = case(kind, rng, work, rtsim)
            code, _, err = run(cmd, work, args.timeout)
            v = verdict(code, err)
            if v:
                findings += 1
                keep = os.path.join(out, "findings", f"{n:05d}-{kind}")
                shutil.copytree(work, keep, dirs_exist_ok=True)
                open(os.path.join(keep, "command.txt"), "w").write(" ".join(map(repr, cmd)) + "\n")
                open(os.path.join(keep, "stderr.txt"), "wb").write(err)
                print(f"case {n} ({kind}): {v}: {err.decode('utf-8', 'replace').strip()[-200:]}")
        finally:
            shutil.rmtree(work, ignore_errors=True)
    shutil.rmtree(config_dir, ignore_errors=True)
    print(
        f"fuzz: {args.cases} cases, seed {args.seed}, {findings} findings"
        + (f" in {out}/findings" if findings else "")
    )
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
