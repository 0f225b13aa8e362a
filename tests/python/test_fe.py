"""FE models through files: groups and fields come back under their own names in .msh (gmsh
physical groups), .vtu (cell data arrays) and .inp (Abaqus element sets); quads are cut into
triangles with a warning; cells femsimp does not simplify are left out with a warning or refused
with strict."""
import warnings

import meshio
import numpy as np
import pytest

from conftest import box_surface, quad_box
from femsimp.fe import from_meshio
import femsimp

FIXED, LOADED = 11, 12  # physical tags


def box_model():
    """The cube's surface in two blocks: side 0 'fixed', the rest 'loaded' (a pressure on side
    1), plus one line cell; groups as gmsh tags, VTK arrays and element sets at once."""
    points, triangles, side = box_surface(12)
    order = np.argsort(side != 0, kind="stable")
    triangles, side = triangles[order], side[order]
    n_fixed = int((side == 0).sum())
    blocks = [("triangle", triangles[:n_fixed]), ("triangle", triangles[n_fixed:]),
              ("line", np.array([[0, 1]]))]
    pressure = np.where(side == 1, 3.0, 0.0)
    split = lambda a, line_value: [a[:n_fixed], a[n_fixed:], np.array([line_value], a.dtype)]
    cell_data = {
        "gmsh:physical": split(np.where(side == 0, FIXED, LOADED).astype(np.int32), 0),
        "gmsh:geometrical": split((side + 1).astype(np.int32), 0),
        "pressure": split(pressure, 0.0),
    }
    cell_sets = {"fixed": [np.arange(n_fixed), np.array([], int), np.array([], int)],
                 "loaded": [np.array([], int), np.arange(len(side) - n_fixed), np.array([], int)]}
    field_data = {"fixed": np.array([FIXED, 2]), "loaded": np.array([LOADED, 2])}
    point_data = {"temperature": points[:, 0] * 100.0}
    return meshio.Mesh(points, blocks, point_data=point_data, cell_data=cell_data,
                       field_data=field_data, cell_sets=cell_sets)


def triangles_of(mesh):
    return sum(len(c.data) for c in mesh.cells if c.type == "triangle")


def per_face(mesh, name):
    return np.concatenate([np.asarray(a) for a, c in zip(mesh.cell_data[name], mesh.cells)
                           if c.type == "triangle"])


def centroids(mesh):
    return np.concatenate([mesh.points[c.data].mean(axis=1) for c in mesh.cells
                           if c.type == "triangle"])


def is_side(c, side):
    axis, high = divmod(side, 2)
    return np.isclose(c[:, axis], high)


@pytest.fixture
def model_file(tmp_path):
    def write(ext):
        path = tmp_path / f"in.{ext}"
        m = box_model()
        if ext == "vtu":  # VTK: arrays only
            m.cell_data["material"] = m.cell_data.pop("gmsh:physical")
            del m.cell_data["gmsh:geometrical"]
            m.cell_sets.clear()
        if ext == "inp":  # Abaqus: element sets only
            m.cell_data.clear()
        if ext == "msh":  # meshio's gmsh 2.2 files cannot mix cell types with element data
            m = meshio.Mesh(m.points, m.cells[:2], point_data=m.point_data,
                            cell_data={k: v[:2] for k, v in m.cell_data.items()},
                            field_data=m.field_data)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            meshio.write(path, m, **({"file_format": "gmsh22", "binary": False}
                                     if ext == "msh" else {}))
        return path
    return write


def simplify_file(client, path, out, line_cell=True):
    if line_cell:
        with pytest.warns(femsimp.FemsimpWarning, match="left out 1 line cells"):
            client.simplify(str(path), output=out, tolerance_relative=0.005)
    else:
        client.simplify(str(path), output=out, tolerance_relative=0.005)
    return meshio.read(out)


def test_msh_physical_groups_by_name(client, model_file, tmp_path):
    path = model_file("msh")
    out = simplify_file(client, path, tmp_path / "out.msh", line_cell=False)
    assert triangles_of(out) < triangles_of(meshio.read(path))
    assert {k: v.tolist() for k, v in out.field_data.items()} == {
        "fixed": [FIXED, 2], "loaded": [LOADED, 2]}
    physical, c = per_face(out, "gmsh:physical"), centroids(out)
    assert np.array_equal(physical == FIXED, is_side(c, 0))
    assert np.array_equal(per_face(out, "pressure") == 3.0, is_side(c, 1))


def test_vtu_cell_data_arrays(client, model_file, tmp_path):
    path = model_file("vtu")
    out = simplify_file(client, path, tmp_path / "out.vtu")
    assert triangles_of(out) < triangles_of(meshio.read(path))
    material, c = per_face(out, "material"), centroids(out)
    assert np.array_equal(material == FIXED, is_side(c, 0))
    assert set(material.tolist()) == {FIXED, LOADED}
    assert np.array_equal(per_face(out, "pressure") == 3.0, is_side(c, 1))
    # Point data comes back with the points (every output point is an input point).
    assert np.allclose(out.point_data["temperature"], out.points[:, 0] * 100.0)


def test_inp_element_sets(client, model_file, tmp_path):
    path = model_file("inp")
    out = simplify_file(client, path, tmp_path / "out.inp")
    assert triangles_of(out) < triangles_of(meshio.read(path))
    assert set(out.cell_sets) == {"fixed", "loaded"}
    starts = np.cumsum([0] + [len(c.data) for c in out.cells])
    fixed = np.zeros(starts[-1], bool)
    for b, members in enumerate(out.cell_sets["fixed"]):
        fixed[starts[b] + np.asarray(members, int)] = True
    assert np.array_equal(fixed, is_side(centroids(out), 0))


def test_meshio_mesh_keeps_blocks_and_coordinates(client):
    model = box_model()
    with pytest.warns(femsimp.FemsimpWarning):
        out = client.simplify(model, tolerance_relative=0.005)
    assert [c.type for c in out.cells] == ["triangle", "triangle"]
    assert set(map(tuple, out.points.tolist())) <= set(map(tuple, model.points.tolist()))
    assert list(out.cell_sets["fixed"][1]) == [] and len(out.cell_sets["fixed"][0]) > 0


def test_strict_refuses_other_cells(client):
    with pytest.raises(femsimp.MeshError, match="left out 1 line cells.*strict"):
        client.simplify(box_model(), strict=True)


def test_too_many_fields_left_out_with_a_warning(client):
    m = box_model()
    n = [len(c.data) for c in m.cells]
    for k in range(4):
        m.cell_data[f"f{k}"] = [np.full(x, float(k)) for x in n]
    with pytest.warns(femsimp.FemsimpWarning, match="left out cell data 'f2'.*'f3'"):
        out = client.simplify(m, ratio=0.5)
    # pressure, f0 and f1 travel; f2 and f3 are over femsimp's three fields.
    assert {"pressure", "f0", "f1"} <= set(out.cell_data) and "f2" not in out.cell_data


def test_quads_are_cut_into_triangles(client):
    """A quad-dominant surface (gmsh's recombined meshes) is simplified whole: its quads become
    triangles (reported), the output is closed and each side keeps its tag and set."""
    points, quads, side = quad_box(12)
    model = meshio.Mesh(points, [("quad", quads)],
                        cell_data={"gmsh:physical": [np.where(side == 0, FIXED, LOADED)
                                                     .astype(np.int32)]},
                        cell_sets={"fixed": [np.flatnonzero(side == 0)]})
    n = len(quads)
    with pytest.warns(femsimp.FemsimpWarning, match=f"cut {n} quad cells into {2 * n} triangles"):
        out = client.simplify(model, tolerance_relative=0.005, strict=True)
    assert [c.type for c in out.cells] == ["triangle"]
    tris = np.asarray(out.cells[0].data)
    assert 0 < len(tris) < 2 * n
    # Closed and consistently oriented: each directed edge once, and its reverse too.
    edges = [tuple(e) for e in np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]],
                                               tris[:, [2, 0]]]).tolist()]
    assert len(set(edges)) == len(edges)
    assert set(edges) == {(b, a) for a, b in edges}
    c = centroids(out)
    assert np.array_equal(per_face(out, "gmsh:physical") == FIXED, is_side(c, 0))
    fixed = np.zeros(len(tris), bool)
    fixed[np.asarray(out.cell_sets["fixed"][0], int)] = True
    assert np.array_equal(fixed, is_side(c, 0))


def test_a_cell_outside_the_points_is_named():
    points, quads, _ = quad_box(2)
    quads = quads.copy()
    quads[1, 2] = len(points)  # one past the last point
    model = meshio.Mesh(points, [("quad", quads)])
    with pytest.raises(femsimp.MeshError,
                       match=f"cell 1 of block 0 \\(quad\\) references a point outside the "
                             f"model's {len(points)}"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            from_meshio(model)


def test_stl_solids_by_name(client, tmp_path):
    """An ASCII STL of one named solid per side (as gmsh and pre-processors export boundary
    patches; meshio alone reads it as one block, or not at all with an upper-case SOLID) keeps
    its solids by name, written back one per side."""
    from femsimp import _stl_solids
    points, triangles, side = box_surface(12)
    lines = []
    for s in range(6):
        lines.append(("SOLID" if s == 3 else "solid") + f" side {s}")
        for t in triangles[side == s]:
            lines += ["facet normal 0 0 0", "outer loop"]
            lines += [f"vertex {x!r} {y!r} {z!r}" for x, y, z in points[t].tolist()]
            lines += ["endloop", "endfacet"]
        lines.append("endsolid")
    path, out = tmp_path / "in.stl", tmp_path / "out.stl"
    path.write_text("\n".join(lines) + "\n")
    assert client.simplify(str(path), output=out, tolerance_relative=0.005) == out
    text = out.read_text()
    assert [l for l in text.splitlines() if l.startswith("solid ")] == \
        [f"solid side {s}" for s in range(6)]
    back = _stl_solids.read(out)
    assert triangles_of(back) < len(triangles)
    for s in range(6):
        block = next(b for b, members in enumerate(back.cell_sets[f"side {s}"]) if len(members))
        assert is_side(back.points[back.cells[block].data].mean(axis=1), s).all()
    # One name is no grouping: meshio reads it, and it is written as meshio writes it.
    one = tmp_path / "one.stl"
    one.write_text("\n".join(l if not l.startswith(("solid", "endsolid")) else
                             l.split()[0] + " part" for l in text.splitlines()) + "\n")
    assert _stl_solids.read(one) is None


def test_malformed_stl_solids_name_the_line(tmp_path):
    path = tmp_path / "bad.stl"
    facet = "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 {} 0\nvertex 0 1 0\n" \
            "endloop\nendfacet\n"
    path.write_text("solid a\n" + facet.format(0) + "endsolid\nsolid b\n" + facet.format("x")
                    + "endsolid\n")
    with pytest.raises(femsimp.MeshError, match=r"bad.stl: cannot read it as a mesh: line 14: "
                                                r"cannot parse 'vertex 1 x 0'"):
        femsimp.inputs.prepare(str(path), output=tmp_path / "out.stl")
