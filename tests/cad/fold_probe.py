"""Folds on many parts: for every export and coarse mesh of a CAD-like set, two fold copies
(make_cad_meshes.break_fold: flat facets of a non-convex quad given its other diagonal) and two
fan copies (a flat vertex moved onto a neighbour from which its fan is not star-shaped, so that
a facet turns over), each run through femsimp's plain call, judged by cad_judge against its
clean source and checked with `tetgen -d` before and after. One line per copy: name, facets
turned over as made, unfolded_edge, fold_left, the output's folds, the judge, tetgen on the
input and the output. docs/FIDELITY.md ("Repair", Folds) has the figures and the command."""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
import make_cad_meshes as m  # noqa: E402

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("meshes", help="a CAD-like set (scripts/make_cad_meshes.py OUTDIR [--only ...])")
ap.add_argument("work", help="where the copies and outputs go")
ap.add_argument("--femsimp", default="build/client/femsimp")
ap.add_argument("--judge", default="build/tests/cad/cad_judge")
ap.add_argument("--tetgen", default="tetgen")
args = ap.parse_args()
SRC, OUT, FEMSIMP, JUDGE = args.meshes, args.work, args.femsimp, args.judge
os.makedirs(OUT, exist_ok=True)


def break_fan(rng, pos, tris):
    """The move break_degenerate avoids: the facets of the fan that turn over, or None."""
    groups = np.zeros(len(tris), dtype=np.int64)
    flat = m.planar_interior_vertices(pos, tris, groups)
    for v in rng.permutation(flat):
        fan = np.flatnonzero((tris == v).any(axis=1))
        for f in fan:
            t = tris[int(f)].tolist()
            u = t[(t.index(int(v)) + 1) % 3]
            turned = int((m.turn_on_move(pos, tris, fan, v, u) < 0).sum())
            if turned:
                pos = pos.copy()
                pos[v] = pos[u]
                return pos, tris, turned
    return None


rows = []
for src in sorted(os.listdir(SRC)):
    if not (src.endswith("_export.stl") or src.endswith("_coarse.off")):
        continue
    pos, tris = m.read_soup(os.path.join(SRC, src))
    stem = src.split(".")[0]
    for seed in range(2):
        rng = np.random.default_rng(100 + seed)
        copies = []
        try:
            p2, t2, _, notes = m.break_fold(rng, pos, tris, np.zeros(len(tris), dtype=np.int64))
            copies.append((f"{stem}_fold{seed}", p2, t2, 2))
        except RuntimeError as e:
            print(stem, "fold:", e)
        fan = break_fan(rng, pos, tris)
        if fan:
            copies.append((f"{stem}_fan{seed}", fan[0], fan[1], fan[2]))
        for name, p, t, made in copies:
            inp = os.path.join(OUT, name + ".off")
            out = os.path.join(OUT, name + ".out.off")
            m.write_off(inp, p, t)
            r = subprocess.run([FEMSIMP, "simplify", inp, out, "--threads", "1", "--quiet",
                                "--stats-json", out + ".json"], capture_output=True, text=True)
            if r.returncode != 0:
                rows.append((name, made, "exit", r.returncode, r.stderr.strip()[:200]))
                continue
            st = json.load(open(out + ".json"))
            counts = st["repair"]["counts"]
            folds_out = st["fidelity"]["output_crossings"]["folds"]["pairs"]
            j = subprocess.run([JUDGE, os.path.join(SRC, src), out, "--tolerance-relative",
                                "0.005", "--max-volume-change", "0.005"],
                               capture_output=True, text=True)
            tin = subprocess.run([args.tetgen, "-d", inp], capture_output=True, text=True).stdout
            tout = subprocess.run([args.tetgen, "-d", out], capture_output=True, text=True).stdout
            rows.append((name, made, counts["unfolded_edge"], counts.get("fold_left", 0), folds_out,
                         "judge ok" if j.returncode == 0 else "JUDGE " + j.stderr.strip()[:150],
                         "in:" + ("refused" if "intersects" in tin else "clean"),
                         "out:" + ("REFUSED" if "intersects" in tout else "clean")))
for r in rows:
    print(*r)
