"""A vertex written wrongly, on many parts: for every mesh named and every seed, a copy with one
vertex moved through the part's far wall (make_cad_meshes' spike breaker), run through femsimp's
plain call, judged by cad_judge against its clean source and against its repaired copy (where
the vertex belonged is lost), and meshed by tetgen. One line per copy. docs/FIDELITY.md
("Repair", Crossings) has the figures and the command."""
import argparse
import json
import os
import subprocess
import sys

import meshio
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
import make_cad_meshes as m  # noqa: E402

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("meshes", help="the CAD set's meshes (scripts/make_cad_meshes.py DIR)")
ap.add_argument("work", help="where the copies and outputs go")
ap.add_argument("--files", default="bracket_coarse.off,flange_coarse.off,knob_coarse.off,"
                "housing_coarse.off,bottle_coarse.off,bracket_fine.off,bracket_export.stl,"
                "flange_export.stl,knob_export.stl,housing_export.stl,bottle_export.stl")
ap.add_argument("--seeds", type=int, default=4)
ap.add_argument("--femsimp", default="build/client/femsimp")
ap.add_argument("--judge", default="build/tests/cad/cad_judge")
ap.add_argument("--tetgen", default="tetgen")
ap.add_argument("--tolerance-relative", default="0.005")
args = ap.parse_args()
os.makedirs(args.work, exist_ok=True)


def judge(src, dst):
    p = subprocess.run([args.judge, src, dst, "--tolerance-relative", args.tolerance_relative],
                       capture_output=True, text=True)
    j = json.loads(p.stdout)
    return f"{100 * j['hausdorff_over_diagonal']:.3f} %" + (" FAIL" if j["failures"] else "")


counts = {"copies": 0, "taken_out": 0, "left": 0, "crossing": 0, "tet": 0, "within": 0}
for name in args.files.split(","):
    source = os.path.join(args.meshes, name)
    mesh = meshio.read(source)
    pos0 = mesh.points.astype(np.float32)
    tris0 = mesh.cells_dict["triangle"].astype(np.int64)
    groups0 = np.zeros(len(tris0), dtype=np.int64)
    for seed in range(args.seeds):
        pos, tris, _, notes = m.BREAKERS["spike"](np.random.default_rng(seed), pos0, tris0, groups0)
        stem = os.path.join(args.work, f"{os.path.splitext(name)[0]}_spike{seed}")
        m.write_off(stem + ".off", pos, tris)
        out, repaired, stats = stem + ".out.off", stem + ".repaired.off", stem + ".json"
        r = subprocess.run([args.femsimp, "simplify", stem + ".off", out, "--quiet",
                            "--stats-json", stats], capture_output=True, text=True)
        subprocess.run([args.femsimp, "simplify", stem + ".off", repaired, "--quiet",
                        "--target-vertices", "4000000000"], capture_output=True)
        s = json.load(open(stats))
        taken = s["repair"]["counts"].get("crossing_removed", 0)
        left = s["repair"]["counts"].get("crossing_left", 0)
        crossing = s["fidelity"]["output_crossings"]["pairs"]
        tet = subprocess.run([args.tetgen, "-pQ", out], capture_output=True).returncode == 0
        to_source, to_repaired = judge(source, out), judge(repaired, out)
        counts["copies"] += 1
        counts["taken_out"] += taken > 0
        counts["left"] += left > 0
        counts["crossing"] += crossing > 0
        counts["tet"] += tet
        counts["within"] += not to_source.endswith("FAIL")
        print(f"{os.path.basename(stem)}: exit {r.returncode}, crossing_removed {taken}, "
              f"crossing_left {left}, output crossings {crossing}, "
              f"{'tet-meshed' if tet else 'TETGEN REFUSES'}; Hausdorff to the source "
              f"{to_source}, to the repaired copy {to_repaired}; repaired copy to the source "
              f"{judge(source, repaired)}", flush=True)
print(json.dumps(counts))
