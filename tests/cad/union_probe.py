"""Bodies of one part exported overlapping, never fused: for each case, gmsh's OpenCASCADE
kernel builds the bodies, meshes each on its own (no fragment, no fuse) and writes them into
one STL; OpenCASCADE's fused solid gives the exact volume. Each STL goes through femsimp's plain
call and with --unite-overlaps; each output is checked with `tetgen -pQ` (it must tet-mesh) and
for crossings (`tetgen -d`). One line per case: the repair's counts, vertices out, the output's
volume against the fused solid's, tetgen. docs/FIDELITY.md ("Bodies exported overlapping") has
the figures and the command."""
import argparse
import json
import math
import os
import subprocess
import sys

import gmsh
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
import make_cad_meshes as m  # noqa: E402


def boss_through_plate(occ):
    return [occ.addBox(0, 0, 0, 60, 40, 8), occ.addCylinder(20, 20, -3, 0, 0, 25, 8)]


def pins_through_block(occ):
    block = occ.addBox(0, 0, 0, 40, 30, 20)
    pin = occ.addCylinder(-5, 15, 10, 50, 0, 0, 4)
    pin2 = occ.addCylinder(20, -5, 6, 0, 40, 0, 3)
    occ.rotate([(3, block)], 20, 15, 10, 1, 1, 0, 0.3)
    return [block, pin, pin2]


def sphere_on_box(occ):
    return [occ.addBox(0, 0, 0, 30, 30, 10), occ.addSphere(15, 15, 12, 7)]


def ribbed_plate(occ):
    tags = [occ.addBox(*box) for box in m.RIBBED_PLATE.values()]
    occ.rotate([(3, tags[2])], 32, 11, 10, 0, 0, 1, math.radians(30))
    return tags


CASES = {"boss_through_plate": boss_through_plate, "pins_through_block": pins_through_block,
         "sphere_on_box": sphere_on_box, "ribbed_plate": ribbed_plate}


def volume_of(path):
    import meshio
    mesh = meshio.read(path)
    p = mesh.points.astype(np.float64)
    t = np.vstack([c.data for c in mesh.cells if c.type == "triangle"])
    return float(np.einsum("ij,ij->i", p[t[:, 0]], np.cross(p[t[:, 1]], p[t[:, 2]])).sum() / 6)


def tetgen_says(tetgen, path):
    p = subprocess.run([tetgen, "-pQ", path], capture_output=True, text=True)
    if p.returncode != 0:
        return "refused"
    d = subprocess.run([tetgen, "-d", path], capture_output=True, text=True)
    return "meshed" if "No faces are intersecting" in d.stdout else "meshed, crossing faces"


ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("work")
ap.add_argument("--femsimp", default="build/client/femsimp")
ap.add_argument("--tetgen", default="tetgen")
ap.add_argument("--divisor", type=float, default=40.0, help="mesh size: the diagonal over this")
ap.add_argument("--break", dest="breakers", default="",
                help="make_cad_meshes breakers applied in turn to each soup before it is written "
                     "(e.g. spike, or crack+flipped+missing)")
ap.add_argument("--seed", type=int, default=1, help="of the breakers' random choices")
args = ap.parse_args()
os.makedirs(args.work, exist_ok=True)
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
for name, build in CASES.items():
    fused_volume = None
    for fused in (True, False):
        gmsh.clear()
        gmsh.model.add(name)
        tags = build(gmsh.model.occ)
        if fused:
            out, _ = gmsh.model.occ.fuse([(3, tags[0])], [(3, t) for t in tags[1:]])
            gmsh.model.occ.synchronize()
            fused_volume = sum(gmsh.model.occ.getMass(3, t) for _, t in out)
            continue
        gmsh.model.occ.synchronize()
        box = gmsh.model.getBoundingBox(-1, -1)
        pos, tris, groups = m.mesh_surfaces(dict(m.VARIANTS["coarse"], divisor=args.divisor),
                                            math.dist(box[:3], box[3:]))
        body = np.zeros(len(tris), dtype=np.int64)
        for tag in tags:
            surfs = [abs(t) for _, t in gmsh.model.getBoundary([(3, tag)], oriented=False)]
            body[np.isin(groups, surfs)] = tag
        for tag in tags:
            tris = m.orient(pos, tris, np.flatnonzero(body == tag))
        broken = []
        rng = np.random.default_rng(args.seed)
        for kind in filter(None, args.breakers.split("+")):
            pos, tris, groups, made = m.BREAKERS[kind](rng, pos, tris, groups)
            broken += [b["kind"] for b in made]
        src = os.path.join(args.work, name + ".stl")
        m.write_stl(src, pos, tris)
    line = [f"{name}: {len(pos)} V{', broken: ' + '+'.join(broken) if broken else ''}, fused "
            f"volume {fused_volume:.6g}"]
    for label, extra in (("plain", []), ("unite", ["--unite-overlaps"])):
        dst = os.path.join(args.work, f"{name}_{label}.off")
        stats = dst + ".json"
        p = subprocess.run([args.femsimp, "simplify", src, dst, "--threads", "1", "--stats-json",
                            stats] + extra, capture_output=True, text=True)
        if p.returncode != 0:
            line.append(f"{label}: exit {p.returncode} {p.stderr.strip()[:200]}")
            continue
        with open(stats) as f:
            s = json.load(f)
        counts = {k: v for k, v in s["repair"]["counts"].items() if v}
        v = volume_of(dst)
        line.append(f"{label}: {counts}, V out {s['output']['vertices']}, crossing pairs "
                    f"{s['fidelity']['output_crossings']['pairs']}, volume {v:.6g} "
                    f"({v / fused_volume - 1:+.3%} of the fused), tetgen {tetgen_says(args.tetgen, dst)}")
    print("; ".join(line), flush=True)
gmsh.finalize()
