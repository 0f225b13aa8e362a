"""FE models (meshio.Mesh) to femsimp's surface and back, groups under their own names.

The surface triangles of the model are simplified, and its quads with them: each is cut into two
triangles along the diagonal whose triangles' smallest angle is larger (as femsimp's own readers
cut polygons), reported with a FemsimpWarning, and its block comes back as triangles. Every other
cell (lines, vertices, tets, quadratic triangles...) is left out with a FemsimpWarning, or refused
(strict=True).
What identifies a triangle travels as its femsimp face group: its cell block, every integer
cell-data array (gmsh:physical, gmsh:geometrical, a VTK MaterialId...) and its membership in
every cell set (Abaqus/CalculiX element sets, gmsh's named groups). Each distinct combination
is one uint32 group id, so every border between groups, sets or blocks stays a feature line,
and the combination of each output face gives back its block, arrays and sets. Float cell-data
arrays of one component are the face fields (at most three). femsimp removes vertices but never
moves one, so every output point is an input point: its coordinates (in the input's dtype),
point data and point sets come back from the input by matching; field_data (gmsh's physical
names) is kept as it was.
"""
import warnings
from collections import Counter

import meshio
import numpy as np

from .errors import FemsimpWarning, MeshError
from .mesh import MAX_FACE_FIELDS, SurfaceMesh, checked, match_points

_BLOCK_LEVEL_SETS = ("gmsh:bounding_entities",)  # entity tags per block, not cell indices
_SURFACE = {"triangle": 1, "quad": 2}  # surface cell types, and the triangles each becomes


def _smallest_angle_cos(points, tris):
    """Per triangle, the cosine of its smallest angle (1: degenerate)."""
    p = points[tris]
    worst = np.full(len(tris), -1.0)
    for k in range(3):
        u, v = p[:, (k + 1) % 3] - p[:, k], p[:, (k + 2) % 3] - p[:, k]
        norms = np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1)
        cos = np.where(norms > 0, (u * v).sum(axis=1) / np.where(norms > 0, norms, 1), 1.0)
        worst = np.maximum(worst, cos)
    return worst


def _cut_quads(points, quads):
    """(2n, 3) triangles of n quads (a, b, c, d) in their winding, quad k's two at rows 2k and
    2k + 1: cut along a-c or b-d, whichever leaves the larger smallest angle."""
    q = np.asarray(quads, dtype=np.int64)
    first = np.stack([q[:, [0, 1, 2]], q[:, [0, 2, 3]]], axis=1)
    second = np.stack([q[:, [0, 1, 3]], q[:, [1, 2, 3]]], axis=1)
    pts = np.asarray(points, dtype=np.float64)
    cos_first = np.maximum(_smallest_angle_cos(pts, first[:, 0]),
                           _smallest_angle_cos(pts, first[:, 1]))
    cos_second = np.maximum(_smallest_angle_cos(pts, second[:, 0]),
                            _smallest_angle_cos(pts, second[:, 1]))
    cut = np.where((cos_second < cos_first)[:, None, None], second, first)
    return cut.reshape(-1, 3)


def _report(messages, strict):
    if not messages:
        return
    text = "; ".join(messages)
    if strict:
        raise MeshError(f"{text} (strict: refused)")
    warnings.warn(f"{text}", FemsimpWarning, stacklevel=4)


class _Plan:
    """What from_meshio kept of the model, to rebuild it around the output."""

    def __init__(self, mesh, tri_ids, used, sent_points, keys, labels, fields, sets):
        self.mesh, self.tri_ids, self.used = mesh, tri_ids, used
        self.sent_points = sent_points  # float32 (n, 3): what the server got
        self.sent_origin = (0.0, 0.0, 0.0)  # what sent_points are measured from
        self.keys = keys      # unique key rows: block, label values..., set memberships...
        self.labels = labels  # [(name, dtype)]
        self.fields = fields  # [(name, dtype)]
        self.sets = sets      # [name]


def from_meshio(mesh, strict=False):
    """(SurfaceMesh of the model's triangles, plan for to_meshio)."""
    problems = []
    blocks = list(mesh.cells)
    tri_ids = [i for i, b in enumerate(blocks) if b.type in _SURFACE]
    others = Counter()
    for b in blocks:
        if b.type not in _SURFACE:
            others[b.type] += len(b.data)
    if others:
        problems.append("left out " + ", ".join(f"{n} {t}" for t, n in others.items())
                        + " cells: femsimp simplifies surface triangles (and quads) only")
    if not tri_ids:
        raise MeshError("the model has no triangle or quad cells (it has "
                        + ", ".join(f"{n} {t}" for t, n in others.items()) + ")")
    # Triangles per cell of each surface block: a quad's two follow each other.
    per_cell = [_SURFACE[blocks[i].type] for i in tri_ids]
    quads = sum(len(blocks[i].data) for i in tri_ids if blocks[i].type == "quad")
    if quads:
        warnings.warn(f"cut {quads} quad cells into {2 * quads} triangles: femsimp simplifies "
                      "triangles, and their blocks come back as triangles", FemsimpWarning,
                      stacklevel=3)
    sizes = np.array([len(blocks[i].data) * m for i, m in zip(tri_ids, per_cell)])
    offsets = np.concatenate(([0], np.cumsum(sizes)))
    nf = int(offsets[-1])
    for i in tri_ids:
        data = np.asarray(blocks[i].data)
        if data.size and (data.min() < 0 or data.max() >= len(mesh.points)):
            cell = int(np.flatnonzero(((data < 0) | (data >= len(mesh.points))).any(axis=1))[0])
            raise MeshError(f"cell {cell} of block {i} ({blocks[i].type}) references a point "
                            f"outside the model's {len(mesh.points)}")
    tris = np.concatenate([np.asarray(blocks[i].data) if m == 1 else
                           _cut_quads(mesh.points, blocks[i].data).astype(
                               np.asarray(blocks[i].data).dtype)
                           for i, m in zip(tri_ids, per_cell)])

    columns = [np.repeat(np.arange(len(tri_ids)), sizes)]
    labels, fields, field_values = [], [], {}
    for name, per_block in mesh.cell_data.items():
        arrays = [np.repeat(np.asarray(per_block[i]), m, axis=0)
                  for i, m in zip(tri_ids, per_cell)]
        kinds = {a.dtype.kind for a in arrays}
        if all(a.ndim == 1 for a in arrays) and kinds <= set("iub"):
            labels.append((name, arrays[0].dtype))
            columns.append(np.concatenate(arrays).astype(np.int64))
        elif all(a.ndim == 1 for a in arrays) and kinds <= set("f"):
            if len(fields) == MAX_FACE_FIELDS:
                problems.append(f"left out cell data '{name}': femsimp carries at most "
                                f"{MAX_FACE_FIELDS} face fields")
                continue
            fields.append((name, arrays[0].dtype))
            field_values[name] = np.concatenate(arrays)
        else:
            shape = "x".join(str(s) for s in arrays[0].shape)
            problems.append(f"left out cell data '{name}' ({arrays[0].dtype}, {shape}): femsimp "
                            "carries integer labels and one-component float fields")
    sets = []
    for name, per_block in mesh.cell_sets.items():
        if name in _BLOCK_LEVEL_SETS:
            continue
        member = np.zeros(nf, dtype=np.int64)
        for k, i in enumerate(tri_ids):
            if i < len(per_block) and per_block[i] is not None and len(per_block[i]):
                cells = np.asarray(per_block[i], dtype=np.int64)
                for t in range(per_cell[k]):  # a quad's triangles are 2c and 2c + 1
                    member[offsets[k] + per_cell[k] * cells + t] = 1
        if member.any():
            sets.append(name)
            columns.append(member)
        elif any(p is not None and len(p) for p in per_block):
            problems.append(f"left out cell set '{name}': none of its cells is a triangle or "
                            "quad")
    _report(problems, strict)

    keys, inverse = _unique_rows(columns)
    groups = (inverse + 1).astype(np.uint32) if len(keys) > 1 else None
    points = np.asarray(mesh.points)
    # Only the points the triangles use are sent (a volume model's inner nodes are not).
    used_mask = np.zeros(len(points), dtype=bool)
    used_mask[tris.ravel()] = True
    if used_mask.all():
        used, local = np.arange(len(points)), tris
    else:
        used = np.flatnonzero(used_mask)
        local = (np.cumsum(used_mask) - 1)[tris]
    surface = checked(points[used], local, groups, field_values)
    plan = _Plan(mesh, tri_ids, used, surface.points, keys, labels, fields, sets)
    plan.sent_origin = surface.origin
    return surface, plan


def _unique_rows(columns):
    """(unique key rows, index of each face's row), as np.unique(axis=0) but by one 1-D unique
    of the columns' codes combined (np.unique over rows sorts bytes, several times slower)."""
    values, codes, radix = [], [], 1
    for col in columns:
        v, inv = np.unique(col, return_inverse=True)
        values.append(v)
        codes.append(inv.ravel().astype(np.int64))
        radix *= len(v)
    if radix == 1:  # one block, no labels or sets: one group
        return np.array([[v[0] for v in values]], dtype=np.int64), np.zeros(len(columns[0]),
                                                                             dtype=np.int64)
    if radix >= 2**62:
        keys, inverse = np.unique(np.column_stack(columns), axis=0, return_inverse=True)
        return keys, inverse.ravel()
    combined = np.zeros(len(columns[0]), dtype=np.int64)
    for v, code in zip(values, codes):
        combined = combined * len(v) + code
    unique, inverse = np.unique(combined, return_inverse=True)
    keys = np.empty((len(unique), len(columns)), dtype=np.int64)
    rest = unique
    for j in range(len(columns) - 1, -1, -1):
        keys[:, j] = values[j][rest % len(values[j])]
        rest = rest // len(values[j])
    return keys, inverse.ravel()


def to_meshio(plan, points32, triangles, groups, fields):
    """The output model: the kept triangle blocks with their cell data and sets, the input's
    points that survived (with their point data and sets), the input's field_data."""
    m = plan.mesh
    idx = match_points(points32, plan.sent_points)
    point_data, point_sets = {}, {}
    if (idx >= 0).all():
        orig = plan.used[idx]
        order = np.argsort(orig, kind="stable")
        kept = orig[order]
        renumber = np.empty(len(order), dtype=np.int64)
        renumber[order] = np.arange(len(order))
        triangles = renumber[triangles]
        points = np.asarray(m.points)[kept]
        for name, values in m.point_data.items():
            point_data[name] = np.asarray(values)[kept]
        new_index = np.full(len(m.points), -1, dtype=np.int64)
        new_index[kept] = np.arange(len(kept))
        for name, members in m.point_sets.items():
            mapped = new_index[np.asarray(members, dtype=np.int64)]
            point_sets[name] = mapped[mapped >= 0].astype(np.asarray(members).dtype)
    else:
        # Not every point is an input point (a server that moves vertices): float32 coordinates,
        # without point data.
        world = points32 + np.asarray(plan.sent_origin)
        points = world.astype(np.asarray(m.points).dtype)[:, :np.asarray(m.points).shape[1]]
        if m.point_data or m.point_sets:
            warnings.warn("output points are not input points: point data and point sets "
                          "left out", FemsimpWarning, stacklevel=3)

    face_keys = plan.keys[groups.astype(np.int64) - 1] if groups is not None else \
        np.repeat(plan.keys[:1], len(triangles), axis=0)
    block_of = face_keys[:, 0]
    cells = []
    cell_data = {name: [] for name, _ in plan.labels + plan.fields}
    cell_sets = {name: [] for name in plan.sets}
    block_sets = {n: [] for n in _BLOCK_LEVEL_SETS if n in m.cell_sets}
    for k, i in enumerate(plan.tri_ids):
        sel = np.flatnonzero(block_of == k)
        if len(sel) == 0:
            warnings.warn(f"cell block {i} ({m.cells[i].type}) has no triangles left",
                          FemsimpWarning, stacklevel=3)
            continue
        cells.append(("triangle", triangles[sel].astype(np.asarray(m.cells[i].data).dtype)))
        for j, (name, dtype) in enumerate(plan.labels):
            cell_data[name].append(face_keys[sel, 1 + j].astype(dtype))
        for name, dtype in plan.fields:
            cell_data[name].append(fields[name][sel].astype(dtype))
        base = 1 + len(plan.labels)
        for j, name in enumerate(plan.sets):
            cell_sets[name].append(np.flatnonzero(face_keys[sel, base + j]).astype(np.int32))
        for name in block_sets:
            per_block = m.cell_sets[name]
            block_sets[name].append(per_block[i] if i < len(per_block) else [])
    cell_sets.update(block_sets)
    return meshio.Mesh(points, cells, point_data=point_data, cell_data=cell_data,
                       field_data=_field_data(m.field_data, cell_data), point_sets=point_sets,
                       cell_sets=cell_sets)


def _field_data(field_data, cell_data):
    """The input's field_data, less gmsh physical names ([tag, dim]) of groups no output cell
    is in (the volume's, a curve's): gmsh readers refuse names without elements."""
    if "gmsh:physical" not in cell_data:
        return dict(field_data)
    tags = set(np.concatenate(cell_data["gmsh:physical"]).tolist()) if cell_data[
        "gmsh:physical"] else set()
    out = {}
    for name, value in field_data.items():
        v = np.asarray(value).ravel()
        if len(v) == 2 and (int(v[1]) != 2 or int(v[0]) not in tags):
            continue
        out[name] = value
    return out


def surface_of(mesh):
    """A meshio.Mesh of a SurfaceMesh: one triangle block, groups as cell data 'femsimp:group',
    fields as cell data of their names."""
    cell_data = {}
    if mesh.groups is not None:
        cell_data["femsimp:group"] = [np.asarray(mesh.groups)]
    for name, values in mesh.fields.items():
        cell_data[name] = [np.asarray(values)]
    return meshio.Mesh(mesh.points, [("triangle", mesh.triangles)], cell_data=cell_data)


__all__ = ["from_meshio", "to_meshio", "surface_of", "SurfaceMesh"]
