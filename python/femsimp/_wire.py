"""The Simplify stream's mesh chunks, encoded and decoded with numpy: no per-element Python.

A MeshChunk's arrays are packed repeated fields: positions and field values are
little-endian float32 bytes (a numpy view), indices and groups are varints (encoded and decoded
a byte position at a time over the whole array). Chunks hold 64 Ki vertices and 64 Ki faces, as
proto/wire.h's ForEachChunk sends them; the checks on what comes back are MeshAssembler's.
Anything else of the stream (spec, progress, result) goes through the generated messages.
"""
import numpy as np

CHUNK_VERTICES = 64 * 1024  # wire::kChunkVertices
CHUNK_FACES = 64 * 1024     # wire::kChunkFaces

# Field numbers of femsimp.proto.
_REQ_CHUNK = 2          # SimplifyRequest.chunk
_RESP_CHUNK = 5         # SimplifyResponse.chunk
_POSITIONS, _INDICES, _GROUPS, _FIELDS = 1, 2, 3, 4  # MeshChunk
_VALUES = 1             # FaceFieldValues.values


def _varint(n):
    out = bytearray()
    while True:
        b = n & 0x7F
        n >>= 7
        if n:
            out.append(b | 0x80)
        else:
            out.append(b)
            return bytes(out)


def _len_field(number, payload):
    return _varint(number << 3 | 2) + _varint(len(payload)) + payload


def encode_varints(values):
    """Packed varint bytes of uint32 values."""
    v = np.asarray(values, dtype=np.uint32).astype(np.uint64)
    nbytes = np.ones(len(v), dtype=np.int64)
    for k in (7, 14, 21, 28):
        nbytes += v >= (1 << k)
    starts = np.cumsum(nbytes) - nbytes
    out = np.empty(int(nbytes.sum()), dtype=np.uint8)
    for k in range(5):
        sel = nbytes > k
        if not sel.any():
            break
        byte = (v[sel] >> np.uint64(7 * k)) & np.uint64(0x7F)
        more = (nbytes[sel] > k + 1).astype(np.uint64) << np.uint64(7)
        out[starts[sel] + k] = (byte | more).astype(np.uint8)
    return out.tobytes()


def decode_varints(buf):
    """uint32 values of packed varint bytes; ValueError when truncated or too long."""
    b = np.frombuffer(buf, dtype=np.uint8)
    if len(b) == 0:
        return np.empty(0, dtype=np.uint32)
    last = b < 0x80
    if not last[-1]:
        raise ValueError("packed varints end inside a value")
    ends = np.flatnonzero(last)
    starts = np.concatenate(([0], ends[:-1] + 1))
    if (ends - starts).max() > 4:
        raise ValueError("a packed value is longer than a uint32 varint")
    value_of = np.repeat(np.arange(len(ends)), ends - starts + 1)
    shift = (np.arange(len(b)) - starts[value_of]) * 7
    parts = (b & 0x7F).astype(np.uint64) << shift.astype(np.uint64)
    values = np.add.reduceat(parts, starts)
    if (values > 0xFFFFFFFF).any():
        raise ValueError("a packed value exceeds uint32")
    return values.astype(np.uint32)


def encode_chunks(mesh):
    """Serialized SimplifyRequests carrying `mesh` (a checked SurfaceMesh), as ForEachChunk."""
    pts = np.ascontiguousarray(mesh.points, dtype="<f4")
    tri = np.ascontiguousarray(mesh.triangles, dtype=np.uint32)
    nv, nf = len(pts), len(tri)
    fields = [np.ascontiguousarray(v, dtype="<f4") for v in mesh.fields.values()]
    out = []
    v = f = 0
    while v < nv or f < nf:
        body = b""
        if v < nv:
            body += _len_field(_POSITIONS, pts[v:v + CHUNK_VERTICES].tobytes())
        if f < nf:
            end = min(nf, f + CHUNK_FACES)
            body += _len_field(_INDICES, encode_varints(tri[f:end].ravel()))
            if mesh.groups is not None:
                body += _len_field(_GROUPS, encode_varints(mesh.groups[f:end]))
            for values in fields:
                body += _len_field(_FIELDS, _len_field(_VALUES, values[f:end].tobytes()))
        out.append(_len_field(_REQ_CHUNK, body))
        v += CHUNK_VERTICES
        f += CHUNK_FACES
    return out


def _read_varint(buf, i):
    shift = value = 0
    while True:
        if i >= len(buf):
            raise ValueError("message ends inside a varint")
        byte = buf[i]
        i += 1
        value |= (byte & 0x7F) << shift
        if byte < 0x80:
            return value, i
        shift += 7


def _fields(buf):
    """(field number, wire type, payload) of a message's top-level fields; payload is a
    memoryview for length-delimited ones, None for what is skipped."""
    i = 0
    mv = memoryview(buf)
    while i < len(buf):
        tag, i = _read_varint(buf, i)
        number, wtype = tag >> 3, tag & 7
        if wtype == 2:
            n, i = _read_varint(buf, i)
            if i + n > len(buf):
                raise ValueError("a field runs past the end of its message")
            yield number, wtype, mv[i:i + n]
            i += n
        elif wtype == 0:
            _, i = _read_varint(buf, i)
            yield number, wtype, None
        elif wtype in (1, 5):
            i += 8 if wtype == 1 else 4
            yield number, wtype, None
        else:
            raise ValueError(f"wire type {wtype} is not supported here")


class Chunk:
    """The arrays of one MeshChunk (numpy, possibly empty)."""
    __slots__ = ("positions", "indices", "groups", "fields")

    def __init__(self, positions, indices, groups, fields):
        self.positions, self.indices, self.groups, self.fields = positions, indices, groups, fields


def decode_chunk(buf):
    """A Chunk from a serialized MeshChunk; None when it uses an encoding this fast path does not
    read (unpacked arrays), for the caller to parse with the generated message instead."""
    parts = {_POSITIONS: [], _INDICES: [], _GROUPS: []}
    fields = []
    for number, wtype, payload in _fields(buf):
        if number in parts:
            if wtype != 2:
                return None
            parts[number].append(payload)
        elif number == _FIELDS:
            values = []
            for n2, w2, p2 in _fields(payload):
                if n2 == _VALUES:
                    if w2 != 2:
                        return None
                    values.append(p2)
            fields.append(np.frombuffer(b"".join(values), dtype="<f4"))
    return Chunk(np.frombuffer(b"".join(parts[_POSITIONS]), dtype="<f4"),
                 decode_varints(b"".join(parts[_INDICES])),
                 decode_varints(b"".join(parts[_GROUPS])), fields)


def chunk_from_message(msg):
    """A Chunk from a parsed MeshChunk message (the slow path)."""
    return Chunk(np.array(msg.positions, dtype=np.float32),
                 np.array(msg.indices, dtype=np.uint32),
                 np.array(msg.face_groups, dtype=np.uint32),
                 [np.array(f.values, dtype=np.float32) for f in msg.face_fields])


def response_deserializer(pb2):
    """Deserializes a SimplifyResponse: a mesh chunk as a Chunk (numpy), anything else as the
    generated message."""
    def deserialize(data):
        if data[:1] == bytes([_RESP_CHUNK << 3 | 2]):
            try:
                items = list(_fields(data))
            except ValueError:
                items = []
            if len(items) == 1 and items[0][0] == _RESP_CHUNK:
                chunk = decode_chunk(items[0][2])
                if chunk is not None:
                    return chunk
        msg = pb2.SimplifyResponse.FromString(data)
        if msg.WhichOneof("payload") == "chunk":
            return chunk_from_message(msg.chunk)
        return msg
    return deserialize


class Assembler:
    """Collects result chunks up to the Result's counts with MeshAssembler's checks: whole
    vertices and faces, nothing past the declared counts, finite values, indices in range."""

    def __init__(self, vertices, faces, has_groups, field_names):
        self.vertices, self.faces = vertices, faces
        self.has_groups = has_groups
        self.field_names = list(field_names)
        self.pos, self.idx, self.grp = [], [], []
        self.fld = [[] for _ in self.field_names]
        self.nv = self.nf = self.ng = 0
        self.nfld = [0] * len(self.field_names)
        self.chunks = 0

    def add(self, c):
        """Appends a Chunk; ValueError naming the chunk and what is wrong."""
        self.chunks += 1
        n = self.chunks
        if len(c.positions) % 3:
            raise ValueError(f"chunk {n}: {len(c.positions)} coordinates is not a multiple of 3")
        if len(c.indices) % 3:
            raise ValueError(f"chunk {n}: {len(c.indices)} indices is not a multiple of 3")
        nv, nf = self.nv + len(c.positions) // 3, self.nf + len(c.indices) // 3
        if nv > self.vertices:
            raise ValueError(f"chunk {n}: vertices past the declared count {self.vertices}")
        if nf > self.faces:
            raise ValueError(f"chunk {n}: faces past the declared count {self.faces}")
        if len(c.groups) and not self.has_groups:
            raise ValueError(f"chunk {n}: face groups sent but the result declared none")
        if self.ng + len(c.groups) > self.faces:
            raise ValueError(f"chunk {n}: face groups past the declared count {self.faces}")
        if c.fields and len(c.fields) != len(self.field_names):
            raise ValueError(f"chunk {n}: {len(c.fields)} face field arrays but the result "
                             f"declares {len(self.field_names)}")
        for k, values in enumerate(c.fields):
            if self.nfld[k] + len(values) > self.faces:
                raise ValueError(f"chunk {n}: values of face field '{self.field_names[k]}' past "
                                 f"the declared count {self.faces}")
            if not np.isfinite(values).all():
                raise ValueError(f"chunk {n}: face field '{self.field_names[k]}' has a "
                                 "non-finite value")
        if not np.isfinite(c.positions).all():
            raise ValueError(f"chunk {n}: a vertex has a non-finite coordinate")
        if len(c.indices) and int(c.indices.max()) >= self.vertices:
            raise ValueError(f"chunk {n}: a face references vertex {int(c.indices.max())} but "
                             f"the result has {self.vertices}")
        self.pos.append(c.positions)
        self.idx.append(c.indices)
        self.grp.append(c.groups)
        for k, values in enumerate(c.fields):
            self.fld[k].append(values)
            self.nfld[k] += len(values)
        self.nv, self.nf, self.ng = nv, nf, self.ng + len(c.groups)

    def finish(self):
        """(points (n, 3) float32, triangles (m, 3) uint32, groups or None, {name: values})."""
        if self.nv != self.vertices or self.nf != self.faces:
            raise ValueError(f"stream ended early: received {self.nv} of {self.vertices} "
                             f"vertices and {self.nf} of {self.faces} faces")
        if self.has_groups and self.ng != self.faces:
            raise ValueError(f"received {self.ng} face groups for {self.faces} faces")
        for k, name in enumerate(self.field_names):
            if self.nfld[k] != self.faces:
                raise ValueError(f"received {self.nfld[k]} values of face field '{name}' for "
                                 f"{self.faces} faces")
        cat = (lambda parts, dt: np.concatenate(parts) if parts else np.empty(0, dtype=dt))
        points = cat(self.pos, np.float32).reshape(-1, 3)
        triangles = cat(self.idx, np.uint32).reshape(-1, 3)
        groups = cat(self.grp, np.uint32) if self.has_groups else None
        fields = {name: cat(self.fld[k], np.float32) for k, name in enumerate(self.field_names)}
        return points, triangles, groups, fields
