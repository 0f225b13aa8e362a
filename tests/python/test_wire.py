"""The numpy chunk codec against the generated messages, and the result checks."""
import numpy as np
import pytest

import femsimp
from femsimp import _wire
from femsimp.mesh import checked


@pytest.fixture(scope="module")
def pb2():
    return femsimp.stubs()[0]


def test_varints_round_trip_at_every_length():
    edges = [0, 1, 127, 128, 16383, 16384, 2**21 - 1, 2**21, 2**28 - 1, 2**28, 2**32 - 1]
    values = np.array(edges * 3, dtype=np.uint32)
    assert np.array_equal(_wire.decode_varints(_wire.encode_varints(values)), values)


def test_truncated_varints_refused():
    with pytest.raises(ValueError, match="end inside a value"):
        _wire.decode_varints(_wire.encode_varints([300])[:-1])


def test_chunks_are_what_protobuf_reads(pb2):
    rng = np.random.default_rng(7)
    nv, nf = 70000, 150000  # more than one chunk of each
    mesh = checked(rng.random((nv, 3)), rng.integers(0, nv, (nf, 3)),
                   rng.integers(0, 2**32, nf, dtype=np.uint64), {"p": rng.random(nf)})
    requests = _wire.encode_chunks(mesh)
    assert len(requests) == 3
    pos, idx, grp, fld = [], [], [], []
    for r in requests:
        c = pb2.SimplifyRequest.FromString(r).chunk
        pos += c.positions
        idx += c.indices
        grp += c.face_groups
        for f in c.face_fields:
            fld += f.values
    assert np.array_equal(np.array(pos, np.float32), mesh.points.ravel())
    assert np.array_equal(np.array(idx, np.uint32), mesh.triangles.ravel())
    assert np.array_equal(np.array(grp, np.uint32), mesh.groups)
    assert np.array_equal(np.array(fld, np.float32), mesh.fields["p"])


def test_response_chunks_decode_like_protobuf(pb2):
    chunk = pb2.MeshChunk(positions=[1.5, -2, 3, 4, 5, 6], indices=[0, 1, 2**31],
                          face_groups=[7], face_fields=[pb2.FaceFieldValues(values=[0.25])])
    data = pb2.SimplifyResponse(chunk=chunk).SerializeToString()
    c = _wire.response_deserializer(pb2)(data)
    assert isinstance(c, _wire.Chunk)
    assert c.positions.tolist() == [1.5, -2, 3, 4, 5, 6]
    assert c.indices.tolist() == [0, 1, 2**31]
    assert c.groups.tolist() == [7] and c.fields[0].tolist() == [0.25]
    progress = pb2.SimplifyResponse(progress=pb2.Progress(vertices_left=9)).SerializeToString()
    assert _wire.response_deserializer(pb2)(progress).progress.vertices_left == 9


def test_assembler_refuses_what_the_result_did_not_declare():
    a = _wire.Assembler(3, 1, False, [])
    bad = _wire.Chunk(np.zeros(9, np.float32), np.array([0, 1, 3], np.uint32),
                      np.empty(0, np.uint32), [])
    with pytest.raises(ValueError, match="chunk 1: a face references vertex 3"):
        a.add(bad)
    short = _wire.Assembler(4, 1, False, [])
    short.add(_wire.Chunk(np.zeros(9, np.float32), np.array([0, 1, 2], np.uint32),
                          np.empty(0, np.uint32), []))
    with pytest.raises(ValueError, match="received 3 of 4 vertices"):
        short.finish()


def test_fast_ply_reads_what_meshio_reads(tmp_path):
    from conftest import sphere_surface
    import meshio
    from femsimp import _fast_ply
    points, triangles = sphere_surface(12)
    path = tmp_path / "s.ply"
    meshio.write(path, meshio.Mesh(points.astype(np.float32), [("triangle", triangles)]),
                 binary=True)
    fast, slow = _fast_ply.read(path), meshio.read(path)
    assert fast is not None
    assert np.array_equal(fast.points, slow.points)
    assert np.array_equal(fast.cells[0].data, slow.cells[0].data)
    # A face property besides the indices (a group): not the fast path.
    faces = np.zeros(len(triangles), [("n", "u1"), ("i", "<i4", 3), ("group", "<i4")])
    faces["n"], faces["i"], faces["group"] = 3, triangles, 7
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(points)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              f"element face {len(triangles)}\nproperty list uchar int vertex_indices\n"
              "property int group\nend_header\n")
    path.write_bytes(header.encode() + points.astype("<f4").tobytes() + faces.tobytes())
    assert _fast_ply.read(path) is None
