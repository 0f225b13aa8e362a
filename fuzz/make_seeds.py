#!/usr/bin/python3
"""Makes the generated part of the fuzz seed corpus (fuzz/seeds/<target>/gen_*): the test meshes
cut down by femsimp itself to a few dozen vertices (so that a seed stays a few KiB, well inside
the fuzzers' -max_len) and written by femsimp's writers and by meshio's (another library's idea
of each format: ASCII and binary STL, PLY and gmsh MSH 2.2 and 4.1), then the request decoder's
seeds from some of them (make_request_seeds). The hand-made tetra_* seeds stay as they are.
femsimp's files come out byte-identical from run to run; meshio's carry the date in a comment.

    fuzz/make_seeds.py BUILD_DIR [TOOL_BUILD_DIR]

BUILD_DIR has client/femsimp; TOOL_BUILD_DIR (default BUILD_DIR) fuzz/make_request_seeds.
"""
import glob
import os
import subprocess
import sys
import tempfile

import meshio

FUZZ = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(FUZZ)
SEEDS = os.path.join(FUZZ, "seeds")

# (test mesh, vertices kept; the paper preset's topology-only run gets there, the fe preset's
# bounds stop far above). femur.off stops at 2328 vertices (feature edges): left out.
SOURCES = [("fandisk.off", 24), ("blade.off", 30), ("rotor_small.off", 40),
           ("fandisk_groups_fields.ply", 30)]


def main():
    build = sys.argv[1]
    tool_build = sys.argv[2] if len(sys.argv) > 2 else build
    cli = os.path.join(build, "client", "femsimp")
    for old in glob.glob(os.path.join(SEEDS, "*", "gen_*")):
        os.remove(old)
    tmp = tempfile.mkdtemp(prefix="femsimp-seeds.")
    for name, keep in SOURCES:
        stem = "gen_" + name.rsplit(".", 1)[0]
        src = os.path.join(REPO, "tests", "data", name)

        def simplify(out, *extra):
            subprocess.run([cli, "simplify", src, out, "--target-vertices", str(keep), "--preset", "paper",
                            "--topology-only", "--max-passes", "1000", "--quiet",
                            "--threads", "1", *extra], check=True, stdout=subprocess.DEVNULL)

        # femsimp's own writers (OFF and STL hold no groups or fields; its STL is binary).
        for ext, target in (("off", "off"), ("obj", "obj"), ("ply", "ply"), ("msh", "msh"),
                            ("stl", "stl_binary")):
            simplify(os.path.join(SEEDS, target, f"{stem}.{ext}"), "--drop-face-data")
        # meshio's, from femsimp's OFF of the same cut-down mesh.
        off = os.path.join(tmp, f"{stem}.off")
        simplify(off, "--drop-face-data")
        mesh = meshio.read(off)
        mesh = meshio.Mesh(mesh.points, [("triangle", mesh.cells_dict["triangle"])])
        writes = [("stl_ascii", "meshio.stl", "stl", {"binary": False}),
                  ("stl_binary", "meshio.stl", "stl", {"binary": True}),
                  ("ply", "meshio_ascii.ply", "ply", {"binary": False}),
                  ("ply", "meshio_binary.ply", "ply", {"binary": True}),
                  ("off", "meshio.off", "off", {}),
                  ("obj", "meshio.obj", "obj", {}),
                  ("msh", "meshio_22_ascii.msh", "gmsh22", {"binary": False}),
                  ("msh", "meshio_22_binary.msh", "gmsh22", {"binary": True}),
                  ("msh", "meshio_41_ascii.msh", "gmsh", {"binary": False}),
                  ("msh", "meshio_41_binary.msh", "gmsh", {"binary": True})]
        for target, suffix, fmt, kw in writes:
            meshio.write(os.path.join(SEEDS, target, f"{stem}_{suffix}"), mesh, file_format=fmt,
                         **kw)
    # The request decoder: a mesh with groups and fields, and two plain ones.
    subprocess.run([os.path.join(tool_build, "fuzz", "make_request_seeds"),
                    os.path.join(SEEDS, "request"),
                    os.path.join(SEEDS, "ply", "tetra_fields_ascii.ply"),
                    os.path.join(SEEDS, "obj", "tetra_groups.obj"),
                    os.path.join(SEEDS, "off", "gen_fandisk.off"),
                    os.path.join(SEEDS, "msh", "gen_blade_meshio_41_binary.msh")], check=True)
    for path in glob.glob(os.path.join(SEEDS, "request", "*")):
        base = os.path.basename(path)
        if not base.startswith("gen_"):
            os.rename(path, os.path.join(SEEDS, "request", "gen_" + base))


if __name__ == "__main__":
    main()
