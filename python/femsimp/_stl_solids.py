"""ASCII STL of several named solids, the way gmsh (Mesh.StlOneSolidPerSurface), Salome and
pre-processors export boundary patches: meshio reads such a file as one block (dropping the
names, and failing on an upper-case SOLID) and writes one solid. Here each solid is a triangle
block and a cell set of its name, and a model of several triangle blocks is written back one
solid per block. Names follow femsimp's readers: the rest of the `solid` line, blanks at its ends
stripped, "default" when empty; a file of one name is left to meshio (no grouping)."""
import meshio
import numpy as np


def _solid_name(line):
    return line.strip()[len("solid"):].strip() or "default"


def read(path):
    """The file as a meshio.Mesh of one triangle block per solid name, or None when it is not an
    ASCII STL of two names or more."""
    with open(path, "rb") as f:
        if not f.read(512).lstrip().lower().startswith(b"solid"):
            return None
        f.seek(0)
        text = f.read().decode("ascii", "replace")
    lines = text.splitlines()
    names = {_solid_name(l) for l in lines if l.strip()[:5].lower() == "solid"}
    if len(names) < 2:
        return None
    order, corners, solid_of = [], [], []
    current = None
    for number, line in enumerate(lines, 1):
        words = line.split()
        if not words:
            continue
        key = words[0].lower()
        if key == "solid":
            current = _solid_name(line)
            if current not in order:
                order.append(current)
        elif key == "vertex":
            if current is None or len(words) != 4:
                raise ValueError(f"line {number}: expected 'vertex x y z' inside a solid")
            try:
                corners.append([float(w) for w in words[1:]])
            except ValueError:
                raise ValueError(f"line {number}: cannot parse '{line.strip()}' as a vertex's "
                                 "three numbers") from None
            if len(corners) % 3 == 0:
                solid_of.append(order.index(current))
    if len(corners) % 3:
        raise ValueError("truncated: the last facet has fewer than 3 corners")
    points, index = np.unique(np.array(corners, dtype=np.float64), axis=0, return_inverse=True)
    triangles = index.reshape(-1, 3)
    solid_of = np.array(solid_of)
    cells = [("triangle", triangles[solid_of == k]) for k in range(len(order))]
    sets = {name: [np.arange(len(c[1])) if k == j else np.array([], dtype=np.int64)
                   for j, c in enumerate(cells)] for k, name in enumerate(order)}
    return meshio.Mesh(points, cells, cell_sets=sets)


def holds_groups(mesh):
    """Whether writing `mesh` to .stl needs named solids: several triangle blocks."""
    return sum(1 for c in mesh.cells if c.type == "triangle") > 1


def write(path, mesh):
    """One solid per triangle block, named by the cell set that holds the whole block (else
    block_<k>); normals from the corners."""
    blocks = [(k, np.asarray(c.data)) for k, c in enumerate(mesh.cells) if c.type == "triangle"]
    points = np.asarray(mesh.points, dtype=np.float64)
    out = []
    for k, tris in blocks:
        name = next((n for n, per_block in mesh.cell_sets.items()
                     if k < len(per_block) and len(per_block[k]) == len(tris) > 0), f"block_{k}")
        out.append(f"solid {name}")
        p = points[tris]
        n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        length = np.linalg.norm(n, axis=1, keepdims=True)
        n = np.divide(n, length, out=np.zeros_like(n), where=length > 0)
        for normal, corners in zip(n.tolist(), p.tolist()):
            out.append("facet normal {!r} {!r} {!r}".format(*normal))
            out.append("outer loop")
            out += ["vertex {!r} {!r} {!r}".format(*c) for c in corners]
            out += ["endloop", "endfacet"]
        out.append(f"endsolid {name}")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
