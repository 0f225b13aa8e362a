"""Several defects in one file, as CAD exports have them: for every part named, copies of its
coarse and export meshes each broken by four to six of make_cad_meshes' breakers in turn
(flipped, duplicate, degenerate, crack, T-junction, missing, unwelded, unreferenced,
fold; with --drop-flat-face first a whole flat CAD face, with --spike first a vertex moved
through the far wall, with --loose last a stray facet and a leftover face, with --twice then the whole broken
part written again, moved by a placement's rounding), each run through femsimp's plain call, judged by cad_judge against its clean source and
checked with `tetgen -d`. One line per copy: name, the defects made, femsimp's exit code, the
repair's changes, the output's crossings and folds, the judge, tetgen on the input and the
output. docs/FIDELITY.md ("Repair", Several defects in one file) has the figures and the
command."""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import gmsh
import meshio
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
import make_cad_meshes as m  # noqa: E402

# Not the bowtie: its copy is two parts, which the clean source is not.
KINDS = ["flipped", "duplicate", "degenerate", "crack", "tjunction", "missing", "unwelded",
         "unreferenced", "fold"]

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("work", help="where the copies and outputs go")
ap.add_argument("--parts", default="bracket,flange,bottle,knob,housing,shaft,elbow,clevis,gear,"
                "rod,tee")
ap.add_argument("--copies", type=int, default=3, help="copies per mesh")
ap.add_argument("--femsimp", default="build/client/femsimp")
ap.add_argument("--judge", default="build/tests/cad/cad_judge")
ap.add_argument("--tetgen", default="tetgen")
ap.add_argument("--groups", action="store_true",
                help="write the copies as OBJ with their CAD faces as groups, and check that "
                "the output keeps every group")
ap.add_argument("--occ", action="store_true",
                help="break OpenCASCADE's own tessellation of each part (what CAD tools export "
                "as STL: slivers, cracks, near-coincident vertices) instead of gmsh's meshes; "
                "judged against it as repaired (the judge's --repaired-input)")
ap.add_argument("--drop-flat-face", action="store_true",
                help="first drop each copy's flat CAD face of most facets whole (the "
                "missing_face breaker), for runs with --mode \"--fill-holes planar\"")
ap.add_argument("--spike", action="store_true",
                help="first move a vertex of each copy through the part's far wall (the spike "
                "breaker: a vertex written wrongly), which repair takes out")
ap.add_argument("--loose", action="store_true",
                help="last add a stray facet and a leftover face beyond the part (the loose "
                "breaker: open bits joined to nothing), which repair removes")
ap.add_argument("--twice", action="store_true",
                help="last write the broken part again, turned by 1e-5 rad and moved by 2e-5 of "
                "the diagonal (the twice breaker: a body written twice), which repair removes")
ap.add_argument("--mode", default="", help="femsimp options beyond the plain call")
ap.add_argument("--tolerance-relative", default="0.005", help="the judge's tolerance")
ap.add_argument("--judge-volume", default="0.005",
                help="the judge's volume budget ('none' where the mode keeps none)")
args = ap.parse_args()
os.makedirs(args.work, exist_ok=True)


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True)


def as_off(path):
    """The mesh at path as an OFF file beside it (tetgen reads no OBJ)."""
    if path.endswith(".off"):
        return path
    mesh = meshio.read(path)
    m.write_off(path + ".off", mesh.points, mesh.cells_dict["triangle"])
    return path + ".off"


def sources():
    """(name, pos, tris, groups) of each part's clean coarse and export meshes."""
    gmsh.initialize(["gmsh", "-nopopup"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.MaxNumThreads2D", 1)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    out = []
    tmpdir = tempfile.mkdtemp()
    for part in args.parts.split(","):
        m.build_part(part)
        xmin, ymin, zmin, xmax, ymax, zmax = gmsh.model.getBoundingBox(-1, -1)
        diag = float(np.linalg.norm([xmax - xmin, ymax - ymin, zmax - zmin]))
        if args.occ:
            pos, tris = m.occ_tessellation(tmpdir, diag)
            out.append((f"{part}_occ", pos, tris, np.zeros(len(tris), dtype=np.int64)))
            continue
        for variant, spec, _ in m.part_variants(part):
            if variant not in ("coarse", "export"):
                continue
            pos, tris, groups = m.mesh_surfaces(spec, diag)
            out.append((f"{part}_{variant}", pos, m.orient(pos, tris), groups))
    gmsh.finalize()
    shutil.rmtree(tmpdir)
    return out


rows = []
for index, (stem, pos0, tris0, groups0) in enumerate(sources()):
    if args.groups:
        clean = os.path.join(args.work, stem + ".obj")
        m.write_obj(clean, pos0, tris0, groups0)
    else:
        clean = os.path.join(args.work, stem + ".off")
        m.write_off(clean, pos0, tris0)
    for seed in range(args.copies):
        rng = np.random.default_rng(1000 * index + seed)
        pos, tris, groups = pos0, tris0, groups0
        made = []
        if args.drop_flat_face:
            try:
                pos, tris, groups, _ = m.BREAKERS["missing_face"](rng, pos, tris, groups)
                made.append("missing_face")
            except RuntimeError:
                break  # no flat face: no copy of this part
        if args.spike:
            try:
                pos, tris, groups, _ = m.BREAKERS["spike"](rng, pos, tris, groups)
                made.append("spike")
            except RuntimeError:
                break
        for kind in rng.permutation(KINDS)[: int(rng.integers(4, 7))]:
            try:
                pos, tris, groups, _ = m.BREAKERS[str(kind)](rng, pos, tris, groups)
                made.append(str(kind))
            except (RuntimeError, ValueError, IndexError, StopIteration):
                pass  # nothing of that kind left to break in this copy
        if args.loose:
            pos, tris, groups, _ = m.BREAKERS["loose"](rng, pos, tris, groups)
            made.append("loose")
        if args.twice:
            pos, tris, groups, _ = m.BREAKERS["twice"](rng, pos, tris, groups)
            made.append("twice")
        name = f"{stem}_mix{seed}"
        ext = "obj" if args.groups else "off"
        inp = os.path.join(args.work, f"{name}.{ext}")
        out = os.path.join(args.work, f"{name}.out.{ext}")
        if args.groups:
            m.write_obj(inp, pos, tris, groups)
        else:
            m.write_off(inp, pos, tris)
        r = run([args.femsimp, "simplify", inp, out, "--threads", "1", "--quiet",
                 "--stats-json", out + ".json"] + args.mode.split())
        if r.returncode != 0:
            rows.append((name, "+".join(made), f"exit {r.returncode}", r.stderr.strip()[:300]))
            continue
        st = json.load(open(out + ".json"))
        changes = {k: v for k, v in st["repair"]["counts"].items() if v}
        crossings = st["fidelity"]["output_crossings"]
        volume = [] if args.judge_volume == "none" else ["--max-volume-change", args.judge_volume]
        j = run([args.judge, clean, out, "--tolerance-relative", args.tolerance_relative] + volume
                + (["--repaired-input"] if args.occ else []))
        if args.spike:  # where the vertex belonged is lost: judged against the repaired copy too
            repaired = os.path.join(args.work, f"{name}.repaired.off")
            run([args.femsimp, "simplify", inp, repaired, "--quiet", "--target-vertices",
                 "4000000000"] + args.mode.split())
            jr = run([args.judge, repaired, out, "--tolerance-relative", args.tolerance_relative]
                     + volume)
            lost = json.loads(run([args.judge, clean, repaired, "--tolerance-relative",
                                   args.tolerance_relative]).stdout)["hausdorff_over_diagonal"]
            j_line = (("judge ok" if j.returncode == 0 else "judge over") +
                      f" (repaired copy off the source {100 * lost:.3f} %, output against it " +
                      ("ok)" if jr.returncode == 0 else "FAILS)"))
        kept = ""
        if args.groups:
            named = lambda path: {ln.split()[1] for ln in open(path) if ln.startswith("g ")}
            lost = named(inp) - named(out)
            kept = f"groups {len(named(out))}/{len(named(inp))}" + (f" LOST {sorted(lost)}"
                                                                    if lost else "")
        tin = run([args.tetgen, "-d", as_off(inp)]).stdout
        tout = run([args.tetgen, "-d", as_off(out)]).stdout
        rows.append((name, "+".join(made), "exit 0",
                     ",".join(f"{k}={v}" for k, v in sorted(changes.items())),
                     f"crossings={crossings['pairs']} folds={crossings['folds']['pairs']}",
                     j_line if args.spike else
                     "judge ok" if j.returncode == 0 else "JUDGE " + (j.stderr or j.stdout)
                     .strip().replace("\n", " ")[:200],
                     "in:" + ("refused" if "intersects" in tin else "clean"),
                     "out:" + ("REFUSED" if "intersects" in tout else "clean"), kept))
        print(*rows[-1], flush=True)
