"""A fast path for the commonest large input: a binary PLY of vertices (x, y, z only) and
triangles (one vertex_indices list of three per face). meshio walks a binary PLY's face lists in
a Python loop (about 1 s per million faces); here they are one numpy structured view. Anything
else (ASCII, other properties, polygons) returns None and meshio reads the file."""
import meshio
import numpy as np

_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
          "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4",
          "uint32": "u4", "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read(path):
    """The file as a meshio.Mesh of one triangle block, or None when it is not that simple."""
    with open(path, "rb") as f:
        if f.read(4) != b"ply\n":
            return None
        header = []
        while True:
            line = f.readline()
            if not line or len(header) > 64:
                return None
            line = line.decode("ascii", "replace").strip()
            if line == "end_header":
                break
            if line and not line.startswith(("comment", "obj_info")):
                header.append(line.split())
        body = f.read()
    formats = {"format binary_little_endian 1.0": "<", "format binary_big_endian 1.0": ">"}
    if not header or " ".join(header[0]) not in formats:
        return None
    order = formats[" ".join(header[0])]
    expected = [["element", "vertex"], ["property"], ["property"], ["property"],
                ["element", "face"], ["property", "list"]]
    if len(header) != 7 or any(h[:len(e)] != e for h, e in zip(header[1:], expected)):
        return None
    names = [h[-1] for h in header[2:5]]
    vtype = {h[1] for h in header[2:5]}
    count_t, index_t = header[6][2], header[6][3]
    if names != ["x", "y", "z"] or len(vtype) != 1 or header[6][4] != "vertex_indices" or \
            not {count_t, index_t, *vtype} <= set(_TYPES):
        return None
    nv, nf = int(header[1][2]), int(header[5][2])
    vdt = np.dtype(order + _TYPES[vtype.pop()])
    fdt = np.dtype([("n", order + _TYPES[count_t]), ("i", order + _TYPES[index_t], 3)])
    if len(body) != nv * 3 * vdt.itemsize + nf * fdt.itemsize:
        return None  # not all triangles (or trailing data): meshio's reader
    points = np.frombuffer(body, vdt, nv * 3).reshape(nv, 3)
    faces = np.frombuffer(body, fdt, nf, offset=nv * 3 * vdt.itemsize)
    if (faces["n"] != 3).any():
        return None
    return meshio.Mesh(points.astype(np.float64 if vdt.itemsize == 8 else np.float32),
                       [("triangle", faces["i"].astype(np.dtype(_TYPES[index_t])))])
