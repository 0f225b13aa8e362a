"""Retries as client/retry.h does them, the stub cache, and the wire's field numbers."""
import os

import grpc
import pytest

from conftest import Server, sphere_surface
import femsimp
from femsimp import _stubs, _wire
from femsimp.client import RetryPolicy, is_retryable, retry_delay


def test_what_is_retried():
    assert is_retryable(grpc.StatusCode.UNAVAILABLE, None)
    assert is_retryable(grpc.StatusCode.RESOURCE_EXHAUSTED, 500)
    assert not is_retryable(grpc.StatusCode.RESOURCE_EXHAUSTED, None)  # a size limit
    assert not is_retryable(grpc.StatusCode.RESOURCE_EXHAUSTED, -1)    # "do not retry"
    assert not is_retryable(grpc.StatusCode.INVALID_ARGUMENT, None)


def test_delays():
    p = RetryPolicy()
    assert retry_delay(p, 1, None, 0.5) == pytest.approx(0.25)
    assert retry_delay(p, 3, None, 0.5) == pytest.approx(1.0)
    assert retry_delay(p, 10, None, 0.5) == pytest.approx(8.0)        # capped
    assert retry_delay(p, 1, None, 0.0) == pytest.approx(0.25 * 0.8)  # jitter down ...
    assert retry_delay(p, 1, 1000, 0.0) == pytest.approx(1.0)         # ... never below a pushback
    assert retry_delay(p, 1, 1000, 0.99) == pytest.approx(1.198)


def test_queue_full_is_retried_after_the_pushback():
    full = Server("--queue_capacity=0")  # refuses every job: queue full, pushback 1000 ms
    try:
        with femsimp.Client(full.address, max_attempts=2) as c:
            with pytest.raises(femsimp.FemsimpError) as e:
                c.simplify(sphere_surface(10), ratio=0.5)
    finally:
        full.stop()
    assert e.value.code == grpc.StatusCode.RESOURCE_EXHAUSTED
    assert e.value.pushback_ms == 1000 and e.value.attempts == 2
    assert "gave up after 2 attempts" in str(e.value)


def test_stub_cache_is_named_by_the_proto():
    import hashlib
    with open(os.path.join(_stubs.CHECKOUT_PROTO_ROOT, _stubs.PROTO_REL), "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()[:20]
    pb2, _ = femsimp.stubs()
    assert os.path.basename(os.path.dirname(os.path.dirname(os.path.dirname(pb2.__file__)))) \
        == digest


def test_wire_field_numbers_are_the_protos():
    pb2, _ = femsimp.stubs()
    chunk = pb2.MeshChunk.DESCRIPTOR.fields_by_name
    assert (chunk["positions"].number, chunk["indices"].number, chunk["face_groups"].number,
            chunk["face_fields"].number) == (_wire._POSITIONS, _wire._INDICES, _wire._GROUPS,
                                             _wire._FIELDS)
    assert pb2.FaceFieldValues.DESCRIPTOR.fields_by_name["values"].number == _wire._VALUES
    assert pb2.SimplifyRequest.DESCRIPTOR.fields_by_name["chunk"].number == _wire._REQ_CHUNK
    assert pb2.SimplifyResponse.DESCRIPTOR.fields_by_name["chunk"].number == _wire._RESP_CHUNK


def test_an_edited_proto_gets_new_stubs(tmp_path):
    """A field added to the proto (as parallel work adds them to Result and JobSpec) is in the
    stubs at the next first use: a new cache folder, no stale copy."""
    import shutil
    import subprocess
    import sys
    from conftest import REPO
    root = tmp_path / "proto"
    shutil.copytree(_stubs.CHECKOUT_PROTO_ROOT, root)
    proto = root / "femsimp" / "v1" / "femsimp.proto"
    text = proto.read_text()
    proto.write_text(text.replace("message Result {", "message Result {\n  string added_here = 999;", 1))
    code = ("import femsimp, femsimp._stubs as s; s.CHECKOUT_PROTO_ROOT = %r; pb2, _ = s.load(); "
            "print('added_here' in pb2.Result.DESCRIPTOR.fields_by_name, pb2.__file__)" % str(root))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": os.path.join(REPO, "python"),
                               "FEMSIMP_CACHE_DIR": str(tmp_path / "cache")})
    assert done.returncode == 0, done.stderr
    found, path = done.stdout.split()
    assert found == "True" and path.startswith(str(tmp_path / "cache"))
