"""femsimp: a Python client of the femsimp simplification service.

    import femsimp
    with femsimp.Client("127.0.0.1:50051") as client:
        out = client.simplify(meshio.read("part.msh"), tolerance_relative=0.005)

simplify() takes numpy arrays, a SurfaceMesh, a meshio.Mesh or a path, streams the surface
triangles with their groups and fields to a femsimp-server, and returns the same kind with
them carried back (fe.py says how FE groups travel). Options are the engine's
(femsimp.OPTIONS; `python3 -m femsimp options`).
"""
from .errors import FemsimpError, FemsimpWarning, MeshError, OptionError
from .options import OPTIONS, Option

__version__ = "0.1.0"


def stubs():
    """(femsimp_pb2, femsimp_pb2_grpc): the messages and stubs of femsimp.v1 (_stubs.py)."""
    from . import _stubs
    return _stubs.load()


def __getattr__(name):
    # The client pulls in grpc and numpy; the option table and errors do not need them.
    if name in ("Client", "Outcome", "Pass"):
        from . import client
        return getattr(client, name)
    if name == "SurfaceMesh":
        from .mesh import SurfaceMesh
        return SurfaceMesh
    raise AttributeError(f"module 'femsimp' has no attribute '{name}'")


__all__ = ["Client", "Outcome", "Pass", "SurfaceMesh", "FemsimpError", "FemsimpWarning",
           "MeshError", "OptionError", "OPTIONS", "Option", "stubs"]
