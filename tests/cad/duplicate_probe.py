"""Bodies written twice on many parts: for every part of a CAD-like set, the coarse mesh with
(a) a copy of itself turned by 1e-5 rad and moved by 2e-5 of the diagonal
(make_cad_meshes.break_twice), (b) OpenCASCADE's own tessellation of the part and (c) its export
mesh appended (the part exported again, tessellated anew), each run through femsimp's plain
call. Each output must be what the part alone gives (the same vertex count and mass line), with
a duplicate_body record per shell of the copy, and pass `tetgen -d`. One line per copy: name, duplicate_body, the
farthest offset as a share of 2V/A, vertices alone and with the copy, the mass lines equal,
tetgen on the output. docs/FIDELITY.md ("Repair", Duplicate bodies) has the figures and the
command."""
import argparse
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
import make_cad_meshes as m  # noqa: E402

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("meshes", help="a CAD-like set (scripts/make_cad_meshes.py OUTDIR [--only ...])")
ap.add_argument("work", help="where the copies and outputs go")
ap.add_argument("--femsimp", default="build/client/femsimp")
ap.add_argument("--tetgen", default="tetgen")
ap.add_argument("--offset", help="--duplicate-body-offset for the runs (default: femsimp's)")
args = ap.parse_args()
os.makedirs(args.work, exist_ok=True)


def run(src, dst):
    extra = ["--duplicate-body-offset", args.offset] if args.offset else []
    p = subprocess.run([args.femsimp, "simplify", src, dst, "--threads", "1"] + extra,
                       capture_output=True, text=True)
    out = p.stdout
    vertices = re.search(r"^vertices: \d+ -> (\d+)", out, re.M)
    mass = re.search(r"^mass: .*$", out, re.M)
    dup = re.search(r"^  duplicate_body +(\d+)", out, re.M)
    share = re.search(r"\(([0-9.e-]+) of its mean thickness", out)
    return (p.returncode, int(vertices.group(1)) if vertices else -1,
            mass.group(0) if mass else "", int(dup.group(1)) if dup else 0,
            share.group(1) if share else "-")


def tetgen_ok(path):
    p = subprocess.run([args.tetgen, "-d", path], capture_output=True, text=True)
    return p.returncode == 0 and "intersects" not in p.stdout


files = sorted(os.listdir(args.meshes))
parts = sorted({f.split("_coarse")[0] for f in files if f.endswith("_coarse.off")})
bad = 0
for part in parts:
    if part in ("sheet", "assembly"):
        continue  # an open surface, and conforming parts that share faces: no closed copies
    base_path = os.path.join(args.meshes, f"{part}_coarse.off")
    pos, tris = m.read_soup(base_path)
    alone = os.path.join(args.work, f"{part}_alone.off")
    rc, v_alone, mass_alone, _, _ = run(base_path, alone)
    copies = {}
    tpos, ttris, _, _ = m.break_twice(np.random.default_rng(7), pos, tris,
                                      np.zeros(len(tris), dtype=np.int64))
    copies["twice"] = (tpos, ttris)
    for other in ("occ_stl.stl", "export.stl"):
        path = os.path.join(args.meshes, f"{part}_{other}")
        if os.path.exists(path):
            opos, otris = m.read_soup(path)
            copies["retess_" + other.split("_")[0].split(".")[0]] = (
                np.concatenate([pos, opos]), np.concatenate([tris, otris + len(pos)]))
    for name, (cpos, ctris) in copies.items():
        src = os.path.join(args.work, f"{part}_{name}.off")
        dst = os.path.join(args.work, f"{part}_{name}_out.off")
        m.write_off(src, cpos, ctris)
        rc, v, mass, dup, share = run(src, dst)
        same = mass == mass_alone and v == v_alone
        tet = rc == 0 and tetgen_ok(dst)
        ok = rc == 0 and dup >= 1 and same and tet
        bad += not ok
        print(f"{part}_{name}: exit {rc}, duplicate_body {dup} (offset {share} of 2V/A), "
              f"vertices {v_alone} alone / {v}, mass {'same' if same else 'differs'}, "
              f"tetgen {'ok' if tet else 'refused'}{'' if ok else '  <-- FAIL'}", flush=True)
print(f"{bad} failed")
sys.exit(1 if bad else 0)
