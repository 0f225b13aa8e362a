"""SurfaceMesh, the triangle soup femsimp sends and receives, and the checks on numpy input."""
from dataclasses import dataclass, field

import numpy as np

from .errors import MeshError

MAX_FACE_FIELDS = 3          # kMaxFaceFields of the engine
MAX_FIELD_NAME_BYTES = 64    # wire::kMaxFieldNameBytes
LOCAL_ORIGIN_FROM = 1e-6     # kLocalOriginFrom of engine/local_origin.h


@dataclass
class SurfaceMesh:
    """Triangles over points, with optional per-face groups (uint32 ids, 0 = no group) and up to
    three named per-face float fields (e.g. a pressure)."""
    points: np.ndarray                     # (n, 3) float
    triangles: np.ndarray                  # (m, 3) integer, counter-clockwise
    groups: np.ndarray = None              # (m,) uint32, or None
    fields: dict = field(default_factory=dict)  # name -> (m,) float
    # Where points are measured from: a point lies at origin + its coordinates. checked() sets
    # it for a part far from the origin (engine/local_origin.h), so that the float32 points it
    # sends keep the part's detail.
    origin: tuple = (0.0, 0.0, 0.0)

    @property
    def num_points(self):
        """Points (vertices), used or not."""
        return len(self.points)

    @property
    def num_triangles(self):
        """Triangles (faces)."""
        return len(self.triangles)


def local_origin(points):
    """LocalOriginOf (engine/local_origin.cc) of float64 points (n, 3): (0, 0, 0) unless float32
    spacing at the largest coordinate exceeds LOCAL_ORIGIN_FROM of the diagonal, else the box's
    centre rounded to float32."""
    if len(points) == 0:
        return (0.0, 0.0, 0.0)
    lo, hi = points.min(axis=0), points.max(axis=0)
    diagonal = float(np.linalg.norm(hi - lo))
    magnitude = float(np.abs(np.concatenate([lo, hi])).max())
    spacing = float(np.spacing(np.float32(magnitude)))
    if not diagonal > 0 or spacing / diagonal <= LOCAL_ORIGIN_FROM:
        return (0.0, 0.0, 0.0)
    return tuple(float(np.float32(0.5 * a + 0.5 * b)) for a, b in zip(lo, hi))


def _first(mask):
    return int(np.flatnonzero(mask)[0])


def checked(points, triangles, groups=None, fields=None):
    """A SurfaceMesh ready for the wire (float32 points relative to local_origin, uint32
    triangles and groups, float32 fields), or MeshError naming the array, the element and what
    is wrong with it."""
    try:
        p = np.asarray(points, dtype=np.float64)
        t = np.asarray(triangles)
    except (TypeError, ValueError) as e:
        raise MeshError(f"points/triangles are not numeric arrays: {e}") from None
    if p.ndim != 2 or p.shape[1] not in (2, 3):
        raise MeshError(f"points: shape {p.shape}, expected (n, 3) (or (n, 2) in a plane)")
    if p.shape[1] == 2:
        p = np.column_stack([p, np.zeros(len(p))])
    if t.ndim != 2 or t.shape[1] != 3:
        raise MeshError(f"triangles: shape {t.shape}, expected (m, 3)")
    if t.size and not np.issubdtype(t.dtype, np.integer):
        raise MeshError(f"triangles: dtype {t.dtype}, expected integer vertex indices")
    if len(t) == 0:
        raise MeshError("triangles: none; femsimp needs at least one triangle")
    bad = ~np.isfinite(p)
    if bad.any():
        v = _first(bad.any(axis=1))
        raise MeshError(f"points: vertex {v} has a non-finite coordinate ({p[v].tolist()})")
    out_of = (t < 0) | (t >= len(p))
    if out_of.any():
        f = _first(out_of.any(axis=1))
        raise MeshError(f"triangles: face {f} references vertex {t[f].tolist()} but there are "
                        f"{len(p)} points")
    g = None
    if groups is not None:
        g = np.asarray(groups)
        if g.shape != (len(t),):
            raise MeshError(f"groups: shape {g.shape}, expected one id per triangle ({len(t)},)")
        if not np.issubdtype(g.dtype, np.integer):
            raise MeshError(f"groups: dtype {g.dtype}, expected integer ids")
        wrong = (g < 0) | (g > np.iinfo(np.uint32).max)
        if wrong.any():
            f = _first(wrong)
            raise MeshError(f"groups: face {f} has id {g[f]}, outside the uint32 range")
        g = g.astype(np.uint32)
    fl = {}
    for name, values in (fields or {}).items():
        if not isinstance(name, str) or not 1 <= len(name.encode()) <= MAX_FIELD_NAME_BYTES:
            raise MeshError(f"fields: name {name!r} must be 1 to {MAX_FIELD_NAME_BYTES} bytes")
        v = np.asarray(values, dtype=np.float64)
        if v.shape != (len(t),):
            raise MeshError(f"fields: '{name}' has shape {v.shape}, expected one value per "
                            f"triangle ({len(t)},)")
        if not np.isfinite(v).all():
            f = _first(~np.isfinite(v))
            raise MeshError(f"fields: '{name}': face {f} has a non-finite value ({v[f]})")
        fl[name] = v.astype(np.float32)
    if len(fl) > MAX_FACE_FIELDS:
        raise MeshError(f"fields: {len(fl)} ({', '.join(fl)}); femsimp carries at most "
                        f"{MAX_FACE_FIELDS}")
    if not np.isfinite(p.astype(np.float32)).all():
        v = _first(~np.isfinite(p.astype(np.float32)).all(axis=1))
        raise MeshError(f"points: vertex {v} ({p[v].tolist()}) does not fit a float32")
    origin = local_origin(p)
    p32 = (p - np.asarray(origin)).astype(np.float32)
    return SurfaceMesh(p32, t.astype(np.uint32), g, fl, origin)


def match_points(found, original):
    """For each row of `found` (float32, (k, 3)), the index of the first row of `original`
    (float32, (n, 3)) with the same coordinates, or -1. femsimp removes vertices but never moves
    one, so every output point is an input point; this maps it back to its input index."""
    orig = np.ascontiguousarray(original, dtype=np.float32).view(np.uint32).reshape(-1, 3)
    want = np.ascontiguousarray(found, dtype=np.float32).view(np.uint32).reshape(-1, 3)
    if len(orig) == 0:
        return np.full(len(want), -1, dtype=np.int64)
    # Rows by a 64-bit hash of their bits (a 1-D sort, far faster than sorting 12-byte rows),
    # each candidate then compared whole.
    order = np.argsort(_row_hash(orig), kind="stable")
    sorted_hash = _row_hash(orig)[order]
    want_hash = _row_hash(want)
    pos = np.minimum(np.searchsorted(sorted_hash, want_hash), len(order) - 1)
    candidate = order[pos]
    same_hash = sorted_hash[pos] == want_hash
    hit = same_hash & (orig[candidate] == want).all(axis=1)
    if (same_hash & ~hit).any():  # two rows sharing a hash: sort the rows themselves
        return _match_rows(want, orig)
    return np.where(hit, candidate, -1)


def _row_hash(rows):
    r = rows.astype(np.uint64)
    with np.errstate(over="ignore"):
        return (r[:, 0] * np.uint64(0x9E3779B97F4A7C15) ^ r[:, 1] * np.uint64(0xC2B2AE3D27D4EB4F)
                ^ r[:, 2] * np.uint64(0x165667B19E3779F9))


def _match_rows(want, orig):
    key = np.dtype((np.void, 12))
    o, w = orig.view(key).ravel(), want.view(key).ravel()
    order = np.argsort(o, kind="stable")
    pos = np.minimum(np.searchsorted(o[order], w), len(o) - 1)
    return np.where(o[order][pos] == w, order[pos], -1)
