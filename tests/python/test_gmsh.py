"""A real gmsh model: an OpenCASCADE box meshed by gmsh with two named physical surface groups
and a physical volume, simplified by `python3 -m femsimp simplify` through the server."""
import os
import subprocess
import sys

import gmsh
import meshio
import numpy as np
import pytest

from conftest import REPO


@pytest.fixture(scope="module")
def gmsh_box(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("gmsh") / "box.msh")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("box")
        gmsh.model.occ.addBox(0, 0, 0, 2, 1, 0.5)
        gmsh.model.occ.synchronize()
        surfaces = [tag for _, tag in gmsh.model.getEntities(2)]
        gmsh.model.addPhysicalGroup(2, surfaces[:1], 1)
        gmsh.model.setPhysicalName(2, 1, "clamped")
        gmsh.model.addPhysicalGroup(2, surfaces[1:], 2)
        gmsh.model.setPhysicalName(2, 2, "pressure surface")
        gmsh.model.addPhysicalGroup(3, [1], 3)
        gmsh.model.setPhysicalName(3, 3, "solid")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.06)
        gmsh.model.mesh.generate(3)
        gmsh.write(path)
    finally:
        gmsh.finalize()
    return path


def physical_triangles(mesh):
    return np.concatenate([np.asarray(d) for d, c in zip(mesh.cell_data["gmsh:physical"],
                                                         mesh.cells) if c.type == "triangle"])


def test_gmsh_model_through_the_cli(server, gmsh_box, tmp_path):
    out = tmp_path / "out.msh"
    done = subprocess.run(
        [sys.executable, "-m", "femsimp", "simplify", gmsh_box, str(out), "--server",
         server.address, "--tolerance-relative", "0.005"],
        capture_output=True, text=True, env={**os.environ, "PYTHONPATH": os.path.join(REPO, "python")})
    assert done.returncode == 0, done.stderr
    assert "left out" in done.stderr and "tetra" in done.stderr  # the volume, reported
    before, after = meshio.read(gmsh_box), meshio.read(out)
    assert len(physical_triangles(after)) < len(physical_triangles(before))
    assert {k: v.tolist() for k, v in after.field_data.items()} == {
        "clamped": [1, 2], "pressure surface": [2, 2]}
    tags = physical_triangles(after)
    assert set(tags.tolist()) == {1, 2}
    # The clamped surface is one flat face of the box: all its triangles lie in one plane.
    tri = np.concatenate([c.data for c in after.cells if c.type == "triangle"])
    clamped = after.points[tri[tags == 1]].reshape(-1, 3)
    assert np.any(np.ptp(clamped, axis=0) < 1e-9)


def test_gmsh_model_strict_refuses_the_volume(server, gmsh_box, tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "femsimp", "simplify", gmsh_box, str(tmp_path / "o.msh"),
         "--server", server.address, "--strict"],
        capture_output=True, text=True, env={**os.environ, "PYTHONPATH": os.path.join(REPO, "python")})
    assert done.returncode == 4, done.stderr
    assert "tetra" in done.stderr and "strict" in done.stderr
    assert not (tmp_path / "o.msh").exists()


def test_readme_example(server, tmp_path):
    """The README's Python example, as written, against the test server."""
    with open(os.path.join(REPO, "README.md")) as f:
        text = f.read()
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    assert "127.0.0.1:50051" in code
    script = tmp_path / "readme_example.py"
    script.write_text(code.replace("127.0.0.1:50051", server.address))
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                          text=True, env={**os.environ, "PYTHONPATH": os.path.join(REPO, "python")})
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "part-simplified.msh").exists()


def test_example_script(server, tmp_path):
    done = subprocess.run(
        [sys.executable, os.path.join(REPO, "python", "examples", "gmsh_part.py"), server.address,
         str(tmp_path / "part.msh")], capture_output=True, text=True,
        env={**os.environ, "PYTHONPATH": os.path.join(REPO, "python")})
    assert done.returncode == 0, done.stderr
    assert "bore:" in done.stdout and "skin:" in done.stdout
