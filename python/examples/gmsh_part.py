#!/usr/bin/python3
"""gmsh builds a part with two named surface groups, femsimp simplifies its surface through a
running femsimp-server, meshio writes the result, and the groups are checked by name.

    build/server/femsimp-server --listen 127.0.0.1:50051 &
    PYTHONPATH=python /usr/bin/python3 python/examples/gmsh_part.py 127.0.0.1:50051 out/part.msh
"""
import os
import sys
import tempfile
import warnings

import gmsh
import meshio
import numpy as np

import femsimp


def make_part():
    """A plate with a hole (OpenCASCADE), meshed in 3D; its hole is 'bore', the rest 'skin'."""
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("part")
    plate = gmsh.model.occ.addBox(0, 0, 0, 4, 2, 0.5)
    hole = gmsh.model.occ.addCylinder(2, 1, -0.1, 0, 0, 0.7, 0.5)
    gmsh.model.occ.cut([(3, plate)], [(3, hole)])
    gmsh.model.occ.synchronize()
    surfaces = [tag for _, tag in gmsh.model.getEntities(2)]
    bore = [s for s in surfaces if gmsh.model.getType(2, s) == "Cylinder"]
    gmsh.model.addPhysicalGroup(2, bore, 1)
    gmsh.model.setPhysicalName(2, 1, "bore")
    gmsh.model.addPhysicalGroup(2, [s for s in surfaces if s not in bore], 2)
    gmsh.model.setPhysicalName(2, 2, "skin")
    gmsh.model.addPhysicalGroup(3, [v for _, v in gmsh.model.getEntities(3)], 3)
    gmsh.model.setPhysicalName(3, 3, "solid")
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.05)
    gmsh.model.mesh.generate(3)
    with tempfile.TemporaryDirectory() as tmp:
        gmsh.write(os.path.join(tmp, "part.msh"))
        gmsh.finalize()
        return meshio.read(os.path.join(tmp, "part.msh"))


def main(server, out_path):
    """Simplifies the part on `server`, writes `out_path` and checks both groups by name."""
    part = make_part()
    with femsimp.Client(server) as client, warnings.catch_warnings(record=True) as left_out:
        warnings.simplefilter("always", femsimp.FemsimpWarning)
        simplified = client.simplify(part, tolerance_relative=0.005)
    for w in left_out:
        print("note:", w.message)  # the tetrahedra: femsimp simplifies the surface
    meshio.write(out_path, simplified, file_format="gmsh22", binary=False)

    check = meshio.read(out_path)
    names = {name: tag for name, (tag, dim) in check.field_data.items() if dim == 2}
    tags = np.concatenate(check.cell_data["gmsh:physical"])
    before = sum(len(c.data) for c in part.cells if c.type == "triangle")
    print(f"{before} -> {len(tags)} surface triangles")
    for name in ("bore", "skin"):
        count = int((tags == names[name]).sum())
        print(f"  {name}: {count} triangles")
        assert count > 0, name
    assert len(tags) < before


if __name__ == "__main__":
    main(*sys.argv[1:3])
