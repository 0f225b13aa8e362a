"""What simplify() accepts, and giving the result back as the same kind:

- a SurfaceMesh                 -> SurfaceMesh
- (points, triangles[, groups[, fields]]) numpy arrays -> a tuple of the same length
- a meshio.Mesh                 -> meshio.Mesh (fe.py: groups, fields, sets by their names)
- a path meshio reads           -> the output path, written by meshio (needs output=...);
                                   an ASCII STL of named solids: one block and cell set each

Output points are mapped back to the input's (femsimp never moves a point): the coordinates come
back in the input's dtype and order, not rounded through the wire's float32.
"""
import os
import pathlib

import numpy as np

from . import _stl_solids, fe
from .errors import FemsimpWarning, MeshError
from .mesh import SurfaceMesh, checked, match_points


class Prepared:
    """The surface to send and how to turn the output into what the caller gave."""

    def __init__(self, surface, restore, label):
        self.surface, self.restore, self.label = surface, restore, label


def _numpy_restore(surface, original_points, kind, user_origin=(0.0, 0.0, 0.0)):
    def restore(points32, triangles, groups, fields):
        idx = match_points(points32, surface.points)
        orig = np.asarray(original_points)
        if (idx >= 0).all():
            order = np.argsort(idx, kind="stable")
            renumber = np.empty(len(order), dtype=np.int64)
            renumber[order] = np.arange(len(order))
            triangles = renumber[triangles]
            points = orig[idx[order]]
        else:
            import warnings
            warnings.warn("output points are not input points: float32 coordinates",
                          FemsimpWarning, stacklevel=3)
            world = points32 + np.asarray(surface.origin) - np.asarray(user_origin)
            points = world[:, :orig.shape[1]].astype(orig.dtype)
        triangles = triangles.astype(np.int64)
        if kind == "surface":
            return SurfaceMesh(points, triangles, groups, dict(fields), tuple(user_origin))
        out = (points, triangles, groups, dict(fields))
        return out[:kind]
    return restore


def write(path, mesh):
    """meshio.write, but .msh as gmsh 2.2 ASCII (physical and elementary tags on each element):
    meshio's 4.1 writer takes its entities from the nodes' gmsh:dim_tags, and once a surface
    keeps only nodes on its curves and corners it has none, so the file cannot be read back (its
    4.1 binary files also lose their physical groups)."""
    import meshio
    if str(path).lower().endswith(".msh"):
        meshio.write(path, mesh, file_format="gmsh22", binary=False)
    elif str(path).lower().endswith(".stl") and _stl_solids.holds_groups(mesh):
        _stl_solids.write(path, mesh)  # meshio would merge the blocks into one solid
    else:
        # gmsh's per-block entity tags are not cell indices: other formats would write them as
        # a set of cells (an Abaqus ELSET of wrong elements).
        mesh.cell_sets.pop("gmsh:bounding_entities", None)
        meshio.write(path, mesh)


def prepare(mesh, strict=False, output=None):
    """A Prepared for any accepted input; MeshError or TypeError when it is not one."""
    if isinstance(mesh, (str, os.PathLike)):
        import meshio
        path = pathlib.Path(mesh)
        if output is None:
            raise TypeError(f"simplify({str(path)!r}): a path input needs output=PATH")
        try:
            model = None
            if path.suffix.lower() == ".ply":
                from . import _fast_ply
                model = _fast_ply.read(path)
            elif path.suffix.lower() == ".stl":
                model = _stl_solids.read(path)
            if model is None:
                model = meshio.read(path)
        except Exception as e:  # meshio raises ReadError, KeyError, ValueError...
            raise MeshError(f"{path}: cannot read it as a mesh: {e}") from e
        surface, plan = fe.from_meshio(model, strict)

        def restore(points32, triangles, groups, fields):
            write(output, fe.to_meshio(plan, points32, triangles, groups, fields))
            return pathlib.Path(output)
        return Prepared(surface, restore, str(path))
    if type(mesh).__module__.startswith("meshio") and hasattr(mesh, "cells"):
        surface, plan = fe.from_meshio(mesh, strict)
        return Prepared(surface, lambda *out: fe.to_meshio(plan, *out), "meshio.Mesh")
    if isinstance(mesh, SurfaceMesh):
        absolute = mesh.points
        if any(mesh.origin):
            absolute = np.asarray(mesh.points, dtype=np.float64) + np.asarray(mesh.origin)
        surface = checked(absolute, mesh.triangles, mesh.groups, mesh.fields)
        return Prepared(surface, _numpy_restore(surface, mesh.points, "surface", mesh.origin),
                        "SurfaceMesh")
    if isinstance(mesh, (tuple, list)) and 2 <= len(mesh) <= 4:
        surface = checked(*mesh)
        return Prepared(surface, _numpy_restore(surface, mesh[0], len(mesh)), "numpy arrays")
    raise TypeError(f"simplify() takes a SurfaceMesh, (points, triangles[, groups[, fields]]), "
                    f"a meshio.Mesh or a path; got {type(mesh).__name__}")
