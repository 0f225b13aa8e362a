#!/usr/bin/python3
"""A real external gRPC client (Debian's python3-grpcio) against femsimp-server: checks that
reflection is off by default, lists the service through reflection (v1alpha) with --reflection,
checks health, runs Simplify on a mesh file."""
import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import time

p = argparse.ArgumentParser()
p.add_argument("--server-bin", required=True)
p.add_argument("--proto-dir", required=True)
p.add_argument("--mesh", required=True)
p.add_argument("--work-dir", required=True)
args = p.parse_args()

# Stubs generated at test time: femsimp.v1 plus health and reflection from grpc-proto. The
# grpc-proto files are copied under other directory names: generated modules under grpc/ would
# be shadowed by the installed grpc package (the proto packages, hence the service names, stay).
os.makedirs(args.work_dir, exist_ok=True)
ext = os.path.join(args.work_dir, "ext")
for src, dst in (("grpc/health/v1/health.proto", "ext_health/health.proto"),
                 ("grpc/reflection/v1alpha/reflection.proto", "ext_reflection/reflection.proto")):
    os.makedirs(os.path.join(ext, os.path.dirname(dst)), exist_ok=True)
    shutil.copyfile(os.path.join("/usr/share/grpc-proto", src), os.path.join(ext, dst))
subprocess.check_call([
    "protoc", f"-I{args.proto_dir}", f"-I{ext}", f"--python_out={args.work_dir}",
    f"--grpc_out={args.work_dir}", "--plugin=protoc-gen-grpc=/usr/bin/grpc_python_plugin",
    "femsimp/v1/femsimp.proto", "ext_health/health.proto", "ext_reflection/reflection.proto"])
sys.path.insert(0, args.work_dir)

import grpc  # noqa: E402
from femsimp.v1 import femsimp_pb2, femsimp_pb2_grpc  # noqa: E402
from ext_health import health_pb2, health_pb2_grpc  # noqa: E402
from ext_reflection import reflection_pb2, reflection_pb2_grpc  # noqa: E402


def read_off(path):
    """Plain-text OFF reader, independent of the C++ reader."""
    tokens = []
    with open(path) as f:
        for line in f:
            line = line.split("#")[0]
            tokens.extend(line.split())
    assert tokens[0] == "OFF", tokens[0]
    nv, nf = int(tokens[1]), int(tokens[2])
    pos = [float(t) for t in tokens[4:4 + 3 * nv]]
    idx, i = [], 4 + 3 * nv
    for _ in range(nf):
        k = int(tokens[i])
        assert k == 3
        idx.extend(int(t) for t in tokens[i + 1:i + 4])
        i += 4
    return pos, idx


def start_server(*extra):
    """femsimp-server on a free port; returns the process and a ready channel to it."""
    proc = subprocess.Popen([args.server_bin, "--listen=127.0.0.1:0", "--metrics_listen=",
                             "--workers=1", *extra], stderr=subprocess.PIPE, text=True)
    port = None
    deadline = time.time() + 30
    while port is None and time.time() < deadline:
        line = proc.stderr.readline()
        m = re.search(r"\(port (\d+)\)", line)
        if m:
            port = int(m.group(1))
    assert port, "server did not report its port"
    chan = grpc.insecure_channel(f"127.0.0.1:{port}")
    grpc.channel_ready_future(chan).result(timeout=10)
    return proc, chan


def stop_server(proc):
    proc.send_signal(signal.SIGTERM)
    try:
        proc.wait(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()


# Reflection is off unless asked for: a plain server does not list its services.
plain, plain_channel = start_server()
try:
    try:
        next(reflection_pb2_grpc.ServerReflectionStub(plain_channel).ServerReflectionInfo(iter([
            reflection_pb2.ServerReflectionRequest(list_services="")])))
        raise AssertionError("reflection answered without --reflection")
    except grpc.RpcError as e:
        assert e.code() == grpc.StatusCode.UNIMPLEMENTED, e.code()
        print("reflection off by default:", e.code())
    # A message gRPC cannot decode (issue 15, item 6): a unary call gets INVALID_ARGUMENT naming
    # the request type, not gRPC's INTERNAL with an empty message; Simplify says that its stream
    # ended or a message could not be decoded, before the spec and in the mesh.
    garbage = b"\xff\xff\xff\xff\x0f"  # a field tag whose varint never ends
    for method in ("GetJob", "CancelJob", "ListJobs", "ServerInfo"):
        try:
            plain_channel.unary_unary(f"/femsimp.v1.Simplifier/{method}")(garbage, timeout=10)
            raise AssertionError(f"{method} accepted an undecodable request")
        except grpc.RpcError as e:
            assert e.code() == grpc.StatusCode.INVALID_ARGUMENT, (method, e.code(), e.details())
            want = f"could not be decoded as femsimp.v1.{method}Request"
            assert want in e.details(), (method, e.details())
    spec = femsimp_pb2.SimplifyRequest(spec=femsimp_pb2.JobSpec(vertex_count=3, face_count=1))
    simplify = plain_channel.stream_stream("/femsimp.v1.Simplifier/Simplify")
    for messages, want in (([garbage], "stream ended before the job spec"),
                           ([spec.SerializeToString(), garbage], "stream ended early")):
        try:
            list(simplify(iter(messages), timeout=10))
            raise AssertionError("Simplify accepted an undecodable message")
        except grpc.RpcError as e:
            assert e.code() == grpc.StatusCode.INVALID_ARGUMENT, (e.code(), e.details())
            assert want in e.details(), e.details()
            assert "could not be decoded as a femsimp.v1.SimplifyRequest" in e.details(), e.details()
    print("undecodable requests: INVALID_ARGUMENT, naming the message type")
finally:
    stop_server(plain)

server, channel = start_server("--reflection")
try:
    # With --reflection, reflection lists the service.
    refl = reflection_pb2_grpc.ServerReflectionStub(channel)
    resp = next(refl.ServerReflectionInfo(iter([
        reflection_pb2.ServerReflectionRequest(list_services="")])))
    services = [s.name for s in resp.list_services_response.service]
    print("services:", services)
    assert "femsimp.v1.Simplifier" in services, services

    # Health: overall and for the service.
    health = health_pb2_grpc.HealthStub(channel)
    for name in ("", "femsimp.v1.Simplifier"):
        st = health.Check(health_pb2.HealthCheckRequest(service=name), timeout=5).status
        assert st == health_pb2.HealthCheckResponse.SERVING, (name, st)

    info = femsimp_pb2_grpc.SimplifierStub(channel).ServerInfo(
        femsimp_pb2.ServerInfoRequest(), timeout=5)
    print("server:", info.version, list(info.backends))

    # Simplify the mesh.
    pos, idx = read_off(args.mesh)
    nv, nf = len(pos) // 3, len(idx) // 3

    def requests():
        spec = femsimp_pb2.JobSpec(vertex_count=nv, face_count=nf, client_label="python")
        spec.options.ratio = 0.5
        yield femsimp_pb2.SimplifyRequest(spec=spec)
        step = 20000
        for v in range(0, max(nv, nf), step):
            yield femsimp_pb2.SimplifyRequest(chunk=femsimp_pb2.MeshChunk(
                positions=pos[3 * v:3 * min(nv, v + step)], indices=idx[3 * v:3 * min(nf, v + step)]))

    stub = femsimp_pb2_grpc.SimplifierStub(channel)
    kinds, out_pos, out_idx, result = [], [], [], None
    for r in stub.Simplify(requests(), timeout=60):
        kind = r.WhichOneof("payload")
        kinds.append(kind)
        if kind == "result":
            result = r.result
        elif kind == "chunk":
            out_pos.extend(r.chunk.positions)
            out_idx.extend(r.chunk.indices)
    assert kinds[0] == "accepted", kinds
    assert "progress" in kinds, kinds
    assert result is not None
    assert kinds.count("progress") == result.passes, (kinds, result.passes)
    print(f"simplified {nv} -> {result.output_vertices} vertices, stop {result.stop_reason}")
    assert result.output_vertices < nv
    assert len(out_pos) == 3 * result.output_vertices
    assert len(out_idx) == 3 * result.output_faces
    assert max(out_idx) < result.output_vertices

    # A malformed stream is INVALID_ARGUMENT with a message.
    try:
        list(stub.Simplify(iter([femsimp_pb2.SimplifyRequest(chunk=femsimp_pb2.MeshChunk())]),
                           timeout=10))
        raise AssertionError("malformed stream accepted")
    except grpc.RpcError as e:
        assert e.code() == grpc.StatusCode.INVALID_ARGUMENT, e.code()
        print("malformed:", e.details())
    print("OK")
finally:
    stop_server(server)
