#!/usr/bin/python3
"""Hostile-but-bounded probe of femsimp-server and the femsimp CLI (issue 15), kept and rerunnable.

Starts its own femsimp-servers on free loopback ports (gRPC and /metrics) with short limits
(--upload_idle_seconds 2, --result_idle_seconds 3, a queue of 4, small size limits), then runs
cases in seven families, each stating the exact gRPC status (or exit code) it expects:

  malformed  malformed Simplify streams: order, counts, arrays, NaN/Inf, face data, options out
             of range, server limits (declared counts, message size, cell back end, memory)
  garbage    undecodable bytes as Simplify messages and as unary requests
  resources  stalled uploads, more stalls than queue slots, an unread result, the per-tenant
             limit, idle connections to /metrics
  job-ends   cancels mid-upload, while queued and mid-run (CancelJob, a dropped call, a client
             deadline, a SIGKILLed client process): every admitted job reaches a terminal state
  security   tokens (none, wrong: UNAUTHENTICATED, never echoed), tenants' isolation, job ids,
             reflection off, refusing plaintext on 0.0.0.0 and a taken port, huge job ids, a
             label that tries to forge a log line
  signals    SIGTERM with jobs running (grace period, UNAVAILABLE, exit 0); SIGKILL and restart
  cli        `femsimp simplify` on seeded random bytes and mutated copies of the test meshes in
             every format: a documented exit code, never a signal or a hang, the file and the
             line/byte named, no raw control bytes in the output

A wrong status code, an empty or overlong (> 1 KiB) message, a message that does not name what
is wrong, a hang (every call has a client deadline), or a dead server is a finding. After the
cases, every server must hold nothing: no job QUEUED/RUNNING (ListJobs), queue depth and running
jobs 0 (/metrics), threads, open descriptors and resident memory (/proc) back within a small
slack of the baseline taken after a warm-up job ("leaks" family).

    scripts/probe.py [--build build] [--quick] [--seed 15] [--json-out FILE] [--keep-work]

--quick runs fewer garbage and CLI cases (under a minute; the ctest service_probe). Exit 0 when
there are no findings, 1 otherwise; each finding is printed with its case, what was expected and
what came.

Where gRPC itself answers, the probe asserts what the server documents: a message above
--max_request_bytes is RESOURCE_EXHAUSTED (gRPC's own check, README "Server flags"); an unary
request gRPC cannot decode is INVALID_ARGUMENT naming the message type (the server's interceptor
replaces gRPC's INTERNAL, README); a stalled upload or unread result is ended by the server's
watchdog, which the client sees as CANCELLED while the job's status says DEADLINE_EXCEEDED.
"""
import argparse
import json
import os
import random
import re
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(REPO, "python"))
import grpc  # noqa: E402
import numpy as np  # noqa: E402
from server_figures import proc_figures, scrape_metrics  # noqa: E402
import femsimp  # noqa: E402

pb2, pb2_grpc = femsimp.stubs()
SC = grpc.StatusCode
SIMPLIFY = "/femsimp.v1.Simplifier/Simplify"
MAX_MESSAGE = 1024  # a status message longer than this is a finding
TERMINAL = (pb2.JOB_STATE_SUCCEEDED, pb2.JOB_STATE_FAILED, pb2.JOB_STATE_CANCELLED)
CALL_TIMEOUT = 30  # every call's client deadline, unless a case sets its own
# How a refusal says where in the file: a line or byte, a face or vertex number of a binary
# file, or, for what is wrong with the file as a whole, its size against what its header
# announces or needs ("header announces 644 triangles (32284 bytes) but the file has 20629
# bytes", "too short for a binary STL (1 bytes, ...)").
WHERE = (r"line \d+|byte \d+|offset \d+|\.\w+:\d+|(face|vertex|triangle|element|facet) \d+|"
         r"first line|header announces|\d+ bytes")
CHANNEL_OPTIONS = [("grpc.initial_reconnect_backoff_ms", 100),
                   ("grpc.min_reconnect_backoff_ms", 100), ("grpc.max_reconnect_backoff_ms", 500)]
FAMILIES = ["malformed", "garbage", "resources", "job-ends", "security", "signals", "cli", "leaks"]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(pred, timeout, step=0.05):
    """Polls pred until it returns a true value or timeout passes; returns the last value."""
    deadline = time.monotonic() + timeout
    while True:
        v = pred()
        if v or time.monotonic() > deadline:
            return v
        time.sleep(step)




# ---------------------------------------------------------------------------------------------
# Meshes


def icosphere(level):
    """A closed sphere: 10 * 4^level + 2 vertices, 20 * 4^level faces (float32, uint32)."""
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, dtype=np.float64) / np.linalg.norm(p) for p in v]
    faces = f
    for _ in range(level):
        mid = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = verts[a] + verts[b]
                verts.append(p / np.linalg.norm(p))
                mid[key] = len(verts) - 1
            return mid[key]
        nf = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = nf
    return (np.array(verts, dtype=np.float32).reshape(-1),
            np.array(faces, dtype=np.uint32).reshape(-1))


SMALL = icosphere(2)   # 162 vertices, 320 faces: a job of milliseconds
MEDIUM = icosphere(5)  # 10242 vertices, 20480 faces: the slow jobs
LARGE = None           # 163842 vertices: made on first use (the unread result)


def large():
    global LARGE
    if LARGE is None:
        LARGE = icosphere(7)
    return LARGE


def spec_msg(mesh=SMALL, label="probe", groups=False, fields=(), **options):
    pos, idx = mesh
    spec = pb2.JobSpec(vertex_count=len(pos) // 3, face_count=len(idx) // 3,
                       has_face_groups=groups, client_label=label, face_field_names=list(fields))
    cell = options.pop("cell", None)
    for k, v in options.items():
        setattr(spec.options, k, v)
    if cell:
        for k, v in cell.items():
            setattr(spec.options.cell, k, v)
    return pb2.SimplifyRequest(spec=spec)


def chunks(mesh=SMALL, per=4096, groups=None, fields=None):
    """The mesh's chunks, at most `per` vertices and faces each (~100 KiB)."""
    pos, idx = mesh
    nv, nf = len(pos) // 3, len(idx) // 3
    out = []
    for start in range(0, max(nv, nf), per):
        c = pb2.MeshChunk()
        if start < nv:
            c.positions.extend(pos[3 * start:3 * min(nv, start + per)].tolist())
        if start < nf:
            end = min(nf, start + per)
            c.indices.extend(idx[3 * start:3 * end].tolist())
            if groups is not None:
                c.face_groups.extend(groups[start:end])
            if fields is not None:
                for values in fields:
                    c.face_fields.add().values.extend(values[start:end])
        out.append(pb2.SimplifyRequest(chunk=c))
    return out


def chunk(positions=(), indices=(), groups=(), fields=None):
    c = pb2.MeshChunk(positions=list(positions), indices=list(indices), face_groups=list(groups))
    for values in fields or []:
        c.face_fields.add().values.extend(values)
    return pb2.SimplifyRequest(chunk=c)


def slow_spec(label="slow"):
    """A job that runs until cancelled (a few candidates per pass, many passes)."""
    return spec_msg(MEDIUM, label=label, preset=pb2.PRESET_PAPER, topology_only=True,
                    candidate_fraction=1e-4, max_passes=100000, reconsider_every=1000000,
                    target_vertices=4, threads=1)


# ---------------------------------------------------------------------------------------------
# Servers


class Server:
    def __init__(self, probe, name, extra=(), port=None, tokens=None):
        self.name = name
        self.port = port or free_port()
        self.metrics_port = free_port()
        self.log_path = os.path.join(probe.work, f"server-{name}.log")
        self.tokens = tokens
        self.args = [os.path.join(probe.build, "server", "femsimp-server"),
                     f"--listen=127.0.0.1:{self.port}",
                     f"--metrics_listen=127.0.0.1:{self.metrics_port}", *extra]
        self.start()

    def start(self):
        self.log = open(self.log_path, "a")
        self.proc = subprocess.Popen(self.args, stdout=self.log, stderr=subprocess.STDOUT)
        # The port first: a channel that tried too early waits out gRPC's reconnect backoff.
        wait_for(lambda: self._listening(), 30, 0.05)
        self.channel = grpc.insecure_channel(f"127.0.0.1:{self.port}", options=CHANNEL_OPTIONS)
        self.stub = pb2_grpc.SimplifierStub(self.channel)
        ok = wait_for(lambda: self._up(), 30, 0.1)
        if not ok:
            raise RuntimeError(f"femsimp-server {self.name} did not come up: "
                               f"{open(self.log_path).read()[-2000:]}")

    def _listening(self):
        if self.proc.poll() is not None:
            return True  # _up says why
        try:
            socket.create_connection(("127.0.0.1", self.port), timeout=1).close()
            return True
        except OSError:
            return False

    def _up(self):
        if self.proc.poll() is not None:
            raise RuntimeError(f"femsimp-server {self.name} exited {self.proc.returncode}: "
                               f"{open(self.log_path).read()[-2000:]}")
        try:
            self.stub.ServerInfo(pb2.ServerInfoRequest(), timeout=2, metadata=self.md())
            return True
        except grpc.RpcError:
            return False

    def md(self, tenant=None):
        if not self.tokens:
            return None
        return (("authorization", f"Bearer {self.tokens[tenant or 'a']}"),)

    def metrics(self):
        return scrape_metrics(self.metrics_port)

    def unfinished(self, tenants=None):
        out = []
        for t in (tenants or ([None] if not self.tokens else list(self.tokens))):
            out += [j for j in self.stub.ListJobs(pb2.ListJobsRequest(), timeout=10,
                                                  metadata=self.md(t)).jobs
                    if j.state in (pb2.JOB_STATE_QUEUED, pb2.JOB_STATE_RUNNING)]
        return out

    def get_job(self, job_id, tenant=None):
        return self.stub.GetJob(pb2.GetJobRequest(job_id=job_id), timeout=10,
                                metadata=self.md(tenant))

    def alive(self):
        return self.proc.poll() is None

    def stop(self, sig=signal.SIGTERM, timeout=60):
        self.proc.send_signal(sig)
        try:
            rc = self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rc = self.proc.wait()
        self.channel.close()
        self.log.close()
        return rc


class Call:
    """A Simplify call on its own thread: requests from a list or a generator, responses kept."""

    def __init__(self, stub_or_channel, requests, timeout=CALL_TIMEOUT, metadata=None,
                 raw=False, read=True):
        self.responses, self.code, self.details = [], None, ""
        self.accepted = threading.Event()
        self.job_id = None
        self.done = threading.Event()
        self.read = read
        if raw:
            fn = stub_or_channel.stream_stream(SIMPLIFY, request_serializer=None,
                                               response_deserializer=None)
        else:
            fn = stub_or_channel.Simplify
        self.call = fn(iter(requests), timeout=timeout, metadata=metadata)
        self.t0 = time.monotonic()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        try:
            for r in self.call:
                self.responses.append(r)
                if not isinstance(r, bytes) and r.HasField("accepted"):
                    self.job_id = r.accepted.job_id
                    self.accepted.set()
                if not self.read:
                    self.accepted.set()
                    return  # stop reading: the server's writes back up
            self.code = SC.OK
        except grpc.RpcError as e:
            self.code, self.details = e.code(), e.details() or ""
        finally:
            self.seconds = time.monotonic() - self.t0
            self.accepted.set()
            self.done.set()

    def wait(self, timeout=CALL_TIMEOUT + 10):
        self.done.wait(timeout)
        return self.code

    def cancel(self):
        self.call.cancel()


class Gate:
    """A request generator that yields its messages, then blocks until released (a stall)."""

    def __init__(self, messages, then=()):
        self.messages, self.then = list(messages), list(then)
        self.release = threading.Event()

    def __iter__(self):
        yield from self.messages
        self.release.wait(120)
        yield from self.then


# ---------------------------------------------------------------------------------------------
# The probe


class Probe:
    def __init__(self, args):
        self.build = os.path.abspath(args.build)
        with open(os.path.join(self.build, "server", "femsimp-server"), "rb") as f:
            self.asan = b"__asan_init" in f.read()
        self.quick = args.quick
        self.seed = args.seed
        self.work = tempfile.mkdtemp(prefix="femsimp-probe.")
        self.keep_work = args.keep_work
        self.verbose = args.verbose
        self.findings = []
        self.stats = {f: {"cases": 0, "findings": 0, "seconds": 0.0} for f in FAMILIES}
        self.family = None
        self.job_ids = []
        self.servers = []
        self.figures = {}
        self.cli_codes = {}  # exit code -> runs, to show what the mutations provoked

    # -- bookkeeping --
    def note(self, text):
        if self.verbose:
            print(f"    {time.monotonic() - self.t_case:6.2f} s  {text}", flush=True)

    def finding(self, case, expected, got):
        self.findings.append({"family": self.family, "case": case, "expected": expected,
                              "got": got})
        self.stats[self.family]["findings"] += 1
        print(f"FINDING [{self.family}] {case}: expected {expected}; got {got}", flush=True)

    def case(self, name, fn, *a, **kw):
        """Runs one case; an exception in it is a finding (the probe could not do what it must)."""
        self.stats[self.family]["cases"] += 1
        t0 = self.t_case = time.monotonic()
        try:
            fn(name, *a, **kw)
        except Exception as e:  # noqa: BLE001  (anything unexpected is reported, not raised)
            self.finding(name, "the case to run", f"{type(e).__name__}: {str(e)[:300]}")
        if self.verbose:
            print(f"  {time.monotonic() - t0:6.2f} s  [{self.family}] {name}", flush=True)

    def check_status(self, name, code, details, want, words=(), seconds=None):
        """The exact code, a non-empty bounded message naming the problem (any of `words`)."""
        if self.verbose:
            print(f"           {name}: {code.name if code else code} '{details[:160]}'", flush=True)
        if code != want:
            what = "no answer within the client deadline (a hang)" \
                if code == SC.DEADLINE_EXCEEDED and want != SC.DEADLINE_EXCEEDED else ""
            self.finding(name, f"{want.name}", f"{code.name if code else code} "
                         f"{what}'{details[:200]}'")
            return False
        if want == SC.OK:
            return True
        if not details:
            self.finding(name, f"{want.name} with a message", f"{code.name} with an empty message")
            return False
        if len(details.encode()) > MAX_MESSAGE:
            self.finding(name, f"a message of at most {MAX_MESSAGE} bytes",
                         f"{len(details.encode())} bytes")
            return False
        if words and not any(w.lower() in details.lower() for w in words):
            self.finding(name, f"a message naming {' or '.join(words)}", f"'{details[:300]}'")
            return False
        return True

    def expect_stream(self, name, server, requests, want, words=(), raw=False, tenant=None,
                      timeout=20):
        c = Call(server.channel if raw else server.stub, requests, timeout=timeout,
                 metadata=server.md(tenant), raw=raw)
        c.wait(timeout + 10)
        if isinstance(requests, Gate):
            requests.release.set()
        if c.job_id:
            self.job_ids.append(c.job_id)
        self.check_status(name, c.code, c.details, want, words)
        if not server.alive():
            self.finding(name, "the server alive", f"exit {server.proc.returncode}")
        return c

    def expect_unary(self, name, fn, request, want, words=(), metadata=None, timeout=10,
                     allow_empty=False):
        try:
            fn(request, timeout=timeout, metadata=metadata)
            code, details = SC.OK, ""
        except grpc.RpcError as e:
            code, details = e.code(), e.details() or ""
        if allow_empty and code == want and not details:
            return code, details
        self.check_status(name, code, details, want, words)
        return code, details

    def wait_terminal(self, name, server, job_id, timeout=20, tenant=None, want_code=None):
        """The job reaches a terminal state (GetJob) within timeout; returns its JobInfo."""
        info = wait_for(lambda: (lambda j: j if j.state in TERMINAL else None)(
            server.get_job(job_id, tenant)), timeout, 0.05)
        if not info:
            j = server.get_job(job_id, tenant)
            self.finding(name, f"job {job_id} in a terminal state within {timeout} s",
                         f"{pb2.JobState.Name(j.state)}")
            return None
        if want_code and info.status_code != want_code:
            self.finding(name, f"job status {want_code}",
                         f"{info.status_code} '{info.status_message[:200]}'")
        return info

    def start_slow(self, server, label="slow", tenant=None, wait_running=True):
        """A job that runs until cancelled; returns its Call once it is RUNNING (or queued)."""
        c = Call(server.stub, [slow_spec(label)] + chunks(MEDIUM), timeout=120,
                 metadata=server.md(tenant))
        if not c.accepted.wait(30) or not c.job_id:
            raise RuntimeError(f"slow job not accepted: {c.code} {c.details}")
        self.job_ids.append(c.job_id)
        if wait_running:
            ok = wait_for(lambda: server.get_job(c.job_id, tenant).passes_started > 0, 30)
            if not ok:
                raise RuntimeError(f"slow job {c.job_id} did not start running")
        return c

    def server(self, name, extra=(), tokens=None, port=None):
        s = Server(self, name, extra, port=port, tokens=tokens)
        self.servers.append(s)
        return s

    def warm_up(self, s, tenant=None):
        """One job through, then a baseline of the process's figures (the pool settled)."""
        c = Call(s.stub, [spec_msg(SMALL, ratio=0.5)] + chunks(SMALL), metadata=s.md(tenant))
        if c.wait() != SC.OK:
            raise RuntimeError(f"warm-up job on {s.name}: {c.code} {c.details}")
        time.sleep(1.0)
        s.baseline = proc_figures(s.proc.pid)

    # -- families --
    def run(self):
        t_all = time.monotonic()
        common = ["--workers=2", "--queue_capacity=4", "--threads_per_job=1",
                  "--upload_idle_seconds=2", "--upload_deadline_seconds=30",
                  "--result_idle_seconds=3", "--grace_period_seconds=3"]
        self.main = self.server("main", common + [
            "--max_vertices=200000", "--max_faces=400000", f"--max_request_bytes={256 << 10}",
            "--max_spes=4", "--max_cell_local_store_mib=2", "--memory_budget_mib=160"])
        tokens_file = os.path.join(self.work, "tokens.csv")
        self.tokens = {"a": "tok-a-" + "%032x" % random.Random(self.seed).getrandbits(128),
                       "b": "tok-b-" + "%032x" % random.Random(self.seed + 1).getrandbits(128)}
        with open(tokens_file, "w") as f:
            f.write(f"{self.tokens['a']},tenant-a\n{self.tokens['b']},tenant-b\n")
        self.auth = self.server("auth", common + [f"--auth_tokens_file={tokens_file}",
                                                  "--max_jobs_per_tenant=2"],
                                tokens=self.tokens)
        self.warm_up(self.main)
        self.warm_up(self.auth)
        for fam, fn in (("malformed", self.malformed), ("garbage", self.garbage),
                        ("resources", self.resources), ("job-ends", self.job_ends),
                        ("security", self.security), ("signals", self.signals),
                        ("cli", self.cli), ("leaks", self.leaks)):
            self.family = fam
            t0 = time.monotonic()
            try:
                fn()
            except Exception as e:  # noqa: BLE001
                self.stats[fam]["cases"] += 1
                self.finding(f"{fam} (family)", "the family to run",
                             f"{type(e).__name__}: {str(e)[:300]}")
            self.stats[fam]["seconds"] = round(time.monotonic() - t0, 1)
        for s in self.servers:
            if s.alive():
                s.stop()
        self.total_seconds = round(time.monotonic() - t_all, 1)

    # 1. Malformed streams ------------------------------------------------------------------
    def malformed(self):
        s = self.main
        S = SMALL
        nv, nf = len(S[0]) // 3, len(S[1]) // 3
        pos, idx = S[0].tolist(), S[1].tolist()
        ok_chunks = chunks(S)
        IA = SC.INVALID_ARGUMENT

        def st(name, reqs, want=IA, words=(), **kw):
            self.case(name, lambda n: self.expect_stream(n, s, reqs, want, words, **kw))

        st("empty stream", [], words=["spec"])
        st("chunk before spec", ok_chunks, words=["spec"])
        st("empty message first", [pb2.SimplifyRequest()], words=["empty", "spec"])
        st("two specs", [spec_msg(), spec_msg()] + ok_chunks, words=["spec"])
        st("spec, chunk, spec", [spec_msg(), chunk(pos[:30]), spec_msg()], words=["spec"])
        st("spec only then close", [spec_msg()], words=["vert", "face", "ended", "half-closed"])
        st("empty message after spec", [spec_msg(), pb2.SimplifyRequest()], words=["empty"])
        for n, kw, w in (("vertex_count 0", {"vertex_count": 0}, "vertex_count"),
                         ("vertex_count 2", {"vertex_count": 2}, "vertex_count"),
                         ("face_count 0", {"face_count": 0}, "face_count")):
            m = spec_msg()
            for k, v in kw.items():
                setattr(m.spec, k, v)
            st(n, [m] + ok_chunks, words=[w])
        st("more vertices than declared", [spec_msg(), chunk(pos + [0, 0, 0], idx)],
           words=["vert"])
        st("fewer vertices than declared", [spec_msg(), chunk(pos[:-3], idx)], words=["vert"])
        st("more faces than declared", [spec_msg(), chunk(pos, idx + [0, 1, 2])],
           words=["face", "ind"])
        st("fewer faces than declared", [spec_msg(), chunk(pos, idx[:-3])],
           words=["face", "ind"])
        st("positions not a multiple of 3", [spec_msg(), chunk(pos[:-1], idx)],
           words=["position", "3"])
        st("indices not a multiple of 3", [spec_msg(), chunk(pos, idx[:-1])],
           words=["ind", "3"])
        st("positions split mid-vertex", [spec_msg(), chunk(pos[:4]), chunk(pos[4:], idx)],
           words=["position", "whole", "3"])
        bad = list(idx)
        bad[7] = nv
        st("index = vertex_count", [spec_msg(), chunk(pos, bad)], words=["references vertex", "range"])
        bad[7] = 2 ** 32 - 1
        st("index 2^32-1", [spec_msg(), chunk(pos, bad)], words=["references vertex", "range"])
        for label, value in (("NaN", float("nan")), ("+Inf", float("inf")),
                             ("-Inf", float("-inf"))):
            p = list(pos)
            p[10] = value
            st(f"{label} coordinate", [spec_msg(), chunk(p, idx)],
               words=["nan", "inf", "finite"])
        st("face_groups without has_face_groups",
           [spec_msg(), chunk(pos, idx, groups=[1] * nf)], words=["group"])
        st("has_face_groups without face_groups", [spec_msg(groups=True), chunk(pos, idx)],
           words=["group"])
        st("face_groups one short", [spec_msg(groups=True), chunk(pos, idx, groups=[1] * (nf - 1))],
           words=["group"])
        st("four face field names", [spec_msg(fields=["a", "b", "c", "d"])] + ok_chunks,
           words=["field"])
        st("duplicate face field names", [spec_msg(fields=["p", "p"])] + ok_chunks,
           words=["field", "distinct", "twice", "duplicate"])
        st("empty face field name", [spec_msg(fields=[""])] + ok_chunks, words=["field"])
        st("65-byte face field name", [spec_msg(fields=["x" * 65])] + ok_chunks, words=["field"])
        st("face_fields entries != names",
           [spec_msg(fields=["p", "q"]), chunk(pos, idx, fields=[[1.0] * nf])], words=["field"])
        st("face field values one short",
           [spec_msg(fields=["p"]), chunk(pos, idx, fields=[[1.0] * (nf - 1)])], words=["field"])
        st("face field value NaN",
           [spec_msg(fields=["p"]), chunk(pos, idx, fields=[[float("nan")] + [1.0] * (nf - 1)])],
           words=["field", "finite", "nan"])
        st("face_fields sent without names", [spec_msg(), chunk(pos, idx, fields=[[1.0] * nf])],
           words=["field"])
        st("client_label 129 bytes", [spec_msg(label="l" * 129)] + ok_chunks, words=["label"])
        # Options out of range: each names its field.
        opts = [("ratio 1.5", {"ratio": 1.5}, "ratio"), ("ratio -0.1", {"ratio": -0.1}, "ratio"),
                ("ratio 1", {"ratio": 1.0}, "ratio"), ("ratio NaN", {"ratio": float("nan")}, "ratio"),
                ("target_vertices 2^63", {"target_vertices": 2 ** 63}, "target"),
                ("target_vertices 2^64-1", {"target_vertices": 2 ** 64 - 1}, "target"),
                ("target_vertices 4000000001", {"target_vertices": 4000000001}, "target"),
                ("min_angle 70", {"min_angle_deg": 70}, "min_angle"),
                ("min_angle -1", {"min_angle_deg": -1}, "min_angle"),
                ("max_normal_deviation 0", {"max_normal_deviation_deg": 0}, "normal"),
                ("max_normal_deviation 181", {"max_normal_deviation_deg": 181}, "normal"),
                ("candidate_fraction 0", {"candidate_fraction": 0}, "candidate"),
                ("candidate_fraction 1.5", {"candidate_fraction": 1.5}, "candidate"),
                ("max_passes 0", {"max_passes": 0}, "max_passes"),
                ("max_passes 100001", {"max_passes": 100001}, "max_passes"),
                ("reconsider_every 0", {"reconsider_every": 0}, "reconsider"),
                ("threads -1", {"threads": -1}, "threads"),
                ("threads 1025", {"threads": 1025}, "threads"),
                ("tolerance -1", {"tolerance": -1}, "tolerance"),
                ("tolerance NaN", {"tolerance": float("nan")}, "tolerance"),
                ("tolerance +Inf", {"tolerance": float("inf")}, "tolerance"),
                ("tolerance_relative 2", {"tolerance_relative": 2}, "tolerance_relative"),
                ("feature_angle 0", {"feature_angle_deg": 0}, "feature"),
                ("max_volume_change 2", {"max_volume_change": 2}, "volume"),
                ("max_centroid_shift -1", {"max_centroid_shift": -1}, "centroid"),
                ("max_inertia_change 1.5", {"max_inertia_change": 1.5}, "inertia"),
                ("max_field_change 0", {"max_field_change": 0}, "field"),
                ("weld_tolerance 0.02", {"weld_tolerance": 0.02}, "weld"),
                ("backend 7", {"backend": 7}, "backend"),
                ("cost 9", {"cost": 9}, "cost"), ("preset 5", {"preset": 5}, "preset"),
                ("schedule 4", {"schedule": 4}, "schedule"),
                ("placement 3", {"placement": 3}, "placement"),
                ("repair 7", {"repair": 7}, "repair"),
                ("cell ls_cache_kib 3", {"backend": pb2.BACKEND_CELL,
                                         "cell": {"ls_cache_kib": 3}}, "ls_cache"),
                ("cell ls_cache_kib 256 (= local store)",
                 {"backend": pb2.BACKEND_CELL, "cell": {"ls_cache_kib": 256}}, "ls_cache"),
                ("cell spes 257", {"backend": pb2.BACKEND_CELL, "cell": {"spes": 257}}, "spes"),
                ("cell spes -1", {"backend": pb2.BACKEND_CELL, "cell": {"spes": -1}}, "spes"),
                ("cell spe_threads 17", {"backend": pb2.BACKEND_CELL,
                                         "cell": {"spe_threads": 17}}, "spe_threads"),
                ("cell local_store_kib 8", {"backend": pb2.BACKEND_CELL,
                                            "cell": {"local_store_kib": 8}}, "local_store")]
        for n, o, w in opts:
            st(f"option {n}", [spec_msg(**dict(o, cell=dict(o.get("cell", {}))))] + ok_chunks,
               words=[w])
        fe = spec_msg()
        fe.spec.fe_check = True
        fe.spec.fe_check_options.poisson_ratio = 0.6
        st("fe_check poisson_ratio 0.6", [fe] + ok_chunks, words=["poisson"])
        fe = spec_msg()
        fe.spec.fe_check = True
        fe.spec.fe_check_options.modes = 51
        st("fe_check modes 51", [fe] + ok_chunks, words=["modes"])
        # Server limits, before the upload (documented: RESOURCE_EXHAUSTED naming the limit;
        # INVALID_ARGUMENT naming the flag for the cell back end).
        RE = SC.RESOURCE_EXHAUSTED
        for n, v, f, w in (("vertex_count above --max_vertices", 200001, nf, "max_vertices"),
                           ("face_count above --max_faces", nv, 400001, "max_faces"),
                           ("vertex_count 2^64-1", 2 ** 64 - 1, nf, "max_vertices")):
            m = spec_msg()
            m.spec.vertex_count, m.spec.face_count = v, f
            st(n, Gate([m]), RE, [w])  # no chunk: refused before the upload
        st("cell spes above --max_spes (4)",
           Gate([spec_msg(backend=pb2.BACKEND_CELL, cell={"spes": 5})]), IA, ["--max_spes"])
        st("cell local store above --max_cell_local_store_mib (2)",
           Gate([spec_msg(backend=pb2.BACKEND_CELL,
                           cell={"spes": 4, "local_store_kib": 1024})]),
           IA, ["--max_cell_local_store_mib"])
        # A message above --max_request_bytes (256 KiB): gRPC's own RESOURCE_EXHAUSTED.
        big = chunk(pos * 200, [])
        st("chunk above --max_request_bytes", [spec_msg(), big], RE, ["larger than max", "max"])
        st("spec above --max_request_bytes", [spec_msg(label="x" * (300 << 10))], RE,
           ["larger than max", "max"])
        # Meshes that arrive whole but are invalid.
        deg = [0, 0, 0] * nf
        st("every face degenerate", [spec_msg(), chunk(pos, deg)], IA, ["mesh", "degenerate"])
        st("degenerate face, repair off", [spec_msg(repair=pb2.REPAIR_MODE_OFF),
                                           chunk(pos, [0, 0, 1] + idx[3:])], IA,
           ["degenerate", "mesh"])
        # A Moebius strip: non-orientable, refused (not repairable).
        mb_pos, mb_idx = [], []
        n = 12
        for i in range(n):
            a = 2 * np.pi * i / n
            for sgn in (-1, 1):
                w = 0.3 * sgn
                mb_pos += [float((1 + w * np.cos(a / 2)) * np.cos(a)),
                           float((1 + w * np.cos(a / 2)) * np.sin(a)), float(w * np.sin(a / 2))]
        for i in range(n):
            a0, a1 = 2 * i, 2 * i + 1
            if i + 1 < n:
                b0, b1 = 2 * (i + 1), 2 * (i + 1) + 1
            else:
                b0, b1 = 1, 0  # the half twist
            mb_idx += [a0, b0, a1, a1, b0, b1]
        mb = pb2.SimplifyRequest(spec=pb2.JobSpec(vertex_count=2 * n, face_count=2 * n))
        st("non-orientable surface", [mb, chunk(mb_pos, mb_idx)], IA, ["orient"])
        # Memory: one job above the whole budget (no pushback); one that does not fit beside an
        # admitted one (pushback).
        m = spec_msg()
        m.spec.vertex_count, m.spec.face_count = 200000, 400000
        big_limit = Server(self, "membudget", ["--memory_budget_mib=64", "--upload_idle_seconds=2"])
        self.servers.append(big_limit)
        c = self.expect_stream("declared mesh above --memory_budget_mib", big_limit, Gate([m]),
                               RE, ["memory"])
        self.stats[self.family]["cases"] += 1
        if c.call.trailing_metadata() and any(k == "grpc-retry-pushback-ms"
                                               for k, _ in c.call.trailing_metadata()):
            self.finding("declared mesh above --memory_budget_mib", "no retry pushback",
                         "grpc-retry-pushback-ms")
        m2 = spec_msg()
        m2.spec.vertex_count, m2.spec.face_count = 60000, 120000  # ~38 MiB each, 64 MiB budget
        gate = Gate([m2])
        held = Call(big_limit.stub, gate, timeout=30)
        held.accepted.wait(10)
        c = self.expect_stream("second job beside an admitted one over the budget", big_limit,
                               Gate([m2]), RE, ["memory"])
        self.stats[self.family]["cases"] += 1
        if not any(k == "grpc-retry-pushback-ms" for k, _ in (c.call.trailing_metadata() or ())):
            self.finding("second job beside an admitted one over the budget",
                         "trailing grpc-retry-pushback-ms", "none")
        gate.release.set()
        held.wait()
        big_limit.baseline = None

    # 2. Garbage ----------------------------------------------------------------------------
    def garbage(self):
        s = self.main
        rng = random.Random(self.seed)
        IA = SC.INVALID_ARGUMENT

        def undecodable(data):
            try:
                pb2.SimplifyRequest.FromString(data)
                return False
            except Exception:  # noqa: BLE001  (DecodeError)
                return True

        blobs = []
        while len(blobs) < (4 if self.quick else 12):
            b = bytes(rng.randrange(256) for _ in range(rng.choice([1, 7, 64, 500, 4000])))
            if undecodable(b):
                blobs.append(b)
        for i, b in enumerate(blobs):
            self.case(f"random bytes #{i} ({len(b)} B) as the first message",
                      lambda n, b=b: self.expect_stream(n, s, [b], IA, ["decod", "spec"],
                                                        raw=True))
        spec_bytes = spec_msg().SerializeToString()
        for cut in (1, 5, len(spec_bytes) // 2, len(spec_bytes) - 1):
            t = spec_bytes[:cut]
            if undecodable(t):
                self.case(f"spec truncated to {cut} of {len(spec_bytes)} bytes",
                          lambda n, t=t: self.expect_stream(n, s, [t], IA, ["decod", "spec"],
                                                            raw=True))
        chunk_bytes = chunks(SMALL)[0].SerializeToString()
        for cut in (3, len(chunk_bytes) // 3):
            t = chunk_bytes[:cut]
            self.case(f"spec, then a chunk truncated to {cut} bytes",
                      lambda n, t=t: self.expect_stream(n, s, [spec_bytes, t], IA,
                                                        ["decod", "half-closed"], raw=True))
        for i, b in enumerate(blobs[:3]):
            self.case(f"spec, then random bytes #{i}",
                      lambda n, b=b: self.expect_stream(n, s, [spec_bytes, b], IA,
                                                        ["decod", "half-closed"], raw=True))
        # Known fields with the wrong wire type decode as unknown fields: an empty message.
        self.case("spec field as a varint (wrong wire type)",
                  lambda n: self.expect_stream(n, s, [b"\x08\x01"], IA, ["empty", "spec"],
                                               raw=True))
        self.case("vertex_count as bytes (wrong wire type)",
                  lambda n: self.expect_stream(n, s, [b"\x0a\x04\x12\x02\x01\x02"], IA,
                                               ["vertex_count"], raw=True))
        bad_utf8 = b"\x0a\x06\x2a\x04\xff\xfe\xfd\xfc"  # spec.client_label: invalid UTF-8
        self.case("client_label not UTF-8",
                  lambda n: self.expect_stream(n, s, [bad_utf8], IA, ["decod", "spec"], raw=True))
        self.case("length prefix beyond the message",
                  lambda n: self.expect_stream(n, s, [b"\x0a\xff\xff\xff\x0f\x00"], IA,
                                               ["decod", "spec"], raw=True))
        # Unary requests gRPC cannot decode: INVALID_ARGUMENT from the server's interceptor.
        for method, typ in (("GetJob", "GetJobRequest"), ("CancelJob", "CancelJobRequest"),
                            ("ListJobs", "ListJobsRequest"), ("ServerInfo", "ServerInfoRequest")):
            fn = s.channel.unary_unary(f"/femsimp.v1.Simplifier/{method}",
                                       request_serializer=None, response_deserializer=None)
            for label, data in (("random bytes", b"\xff\xfe" + blobs[0]),
                                ("invalid UTF-8 string", b"\x0a\x02\xff\xfe")):
                if method in ("ListJobs", "ServerInfo") and label != "random bytes":
                    continue
                self.case(f"{method}: {label}",
                          lambda n, fn=fn, data=data, typ=typ: self.expect_unary(
                              n, fn, data, IA, [typ]))
        unknown = s.channel.unary_unary("/femsimp.v1.Simplifier/NoSuchMethod",
                                        request_serializer=None, response_deserializer=None)
        # gRPC's own answer to a method no service has (before any femsimp code): UNIMPLEMENTED,
        # with an empty message in gRPC C++ 1.51; only the code is asserted.
        self.case("unknown method", lambda n: self.expect_unary(n, unknown, b"", SC.UNIMPLEMENTED,
                                                                allow_empty=True))

    # 3. Bounded resources ------------------------------------------------------------------
    def resources(self):
        s = self.main
        S = SMALL

        def stalled_upload(name, messages, phase):
            gate = Gate(messages)
            c = Call(s.stub, gate, timeout=30)
            c.wait(15)
            gate.release.set()
            # The watchdog cancels the call: the client sees CANCELLED, the job DEADLINE_EXCEEDED.
            if c.code is None:
                self.finding(name, "the call ended by --upload_idle_seconds 2", "still open at 15 s")
                return
            self.check_status(name, c.code, c.details, SC.CANCELLED)
            if c.seconds > 8:
                self.finding(name, "the end within ~2 s (+ slack)", f"{c.seconds:.1f} s")
            if c.job_id:
                self.job_ids.append(c.job_id)
                info = self.wait_terminal(name, s, c.job_id, want_code="DEADLINE_EXCEEDED")
                if info and "upload_idle_seconds" not in info.status_message:
                    self.finding(name, "the job's status naming --upload_idle_seconds",
                                 f"'{info.status_message}'")
            elif phase != "before the spec":
                self.finding(name, "an Accepted job id", "none")

        self.case("stall before the spec", stalled_upload, [], "before the spec")
        self.case("stall after the spec", stalled_upload, [spec_msg()], "after the spec")
        self.case("stall mid-upload", stalled_upload, [spec_msg(), chunk(S[0][:30].tolist())],
                  "mid-upload")

        def overfill(name):
            gates = [Gate([spec_msg(label=f"stall{i}")]) for i in range(6)]
            calls = [Call(s.stub, g, timeout=30) for g in gates]
            for c in calls:
                c.accepted.wait(10)
            refused = [c for c in calls if c.code == SC.RESOURCE_EXHAUSTED]
            admitted = [c for c in calls if c.job_id]
            self.job_ids += [c.job_id for c in admitted]
            if len(admitted) != 4 or len(refused) != 2:
                self.finding(name, "4 stalled uploads admitted (queue_capacity 4), 2 refused "
                             "RESOURCE_EXHAUSTED", f"{len(admitted)} admitted, {len(refused)} "
                             f"refused, codes {[c.code for c in calls]}")
            for c in refused:
                if not any(k == "grpc-retry-pushback-ms"
                           for k, _ in (c.call.trailing_metadata() or ())):
                    self.finding(name, "the refusal with grpc-retry-pushback-ms", "none")
                    break
            # Another client gets in once the stalls time out (2 s), well within 10 s.
            t0 = time.monotonic()
            while True:
                c = Call(s.stub, [spec_msg(label="after-stalls")] + chunks(S), timeout=20)
                c.wait()
                if c.code == SC.OK or time.monotonic() - t0 > 10:
                    break
                time.sleep(0.2)
            self.check_status(name + ": a later job", c.code, c.details, SC.OK)
            if c.code == SC.OK and time.monotonic() - t0 > 8:
                self.finding(name, "a later job within ~2 s", f"{time.monotonic() - t0:.1f} s")
            # Released only once every stall has ended: a half-close before the watchdog fires
            # would end an upload as INVALID_ARGUMENT ("stream ended early"), rightly.
            for c in calls:
                c.wait(20)
            for g in gates:
                g.release.set()
            for c in admitted:
                self.wait_terminal(name, s, c.job_id, want_code="DEADLINE_EXCEEDED")

        self.case("more stalled uploads than queue slots", overfill)

        def unread_result(name):
            mesh = large()
            before = s.metrics().get('femsimp_jobs_total{status="DEADLINE_EXCEEDED"}', 0)
            # A connection of its own without BDP probing: the client's window then stays at
            # gRPC's 4 MiB. With probing it may grow past the result (a server slow to answer
            # pings, as under ASan, makes the estimate large): the whole result then fits unread
            # and the call ends OK (CI on 5550440, the result then 4.8 MB).
            channel = grpc.insecure_channel(
                f"127.0.0.1:{s.port}", options=CHANNEL_OPTIONS + [
                    ("grpc.http2.bdp_probe", 0), ("grpc.use_local_subchannel_pool", 1)])
            # Three face fields make the result ~8.7 MB, twice that window (the mesh alone, 4.8 MB,
            # is too close to it); 4096 faces a chunk stay under --max_request_bytes.
            nf = len(mesh[1]) // 3
            fields = [[float(k % 7 + f) for k in range(nf)] for f in range(3)]
            c = Call(pb2_grpc.SimplifierStub(channel),
                     [spec_msg(mesh, fields=["p", "q", "r"], preset=pb2.PRESET_PAPER, max_passes=1,
                               candidate_fraction=0.01, threads=1)] +
                     chunks(mesh, per=4096, fields=fields), timeout=60, read=False)
            c.accepted.wait(30)
            ids = []

            def find():
                jobs = s.stub.ListJobs(pb2.ListJobsRequest(include_finished=True), timeout=10).jobs
                mine = [j for j in jobs if j.input_vertices == len(mesh[0]) // 3]
                return mine[0] if mine else None
            j = wait_for(find, 30, 0.1)
            if not j:
                self.finding(name, "the job listed", "not found")
                c.cancel()
                channel.close()
                return
            ids.append(j.job_id)
            self.job_ids.append(j.job_id)
            # Ended by the watchdog (3 s idle) after the engine's run, counted DEADLINE_EXCEEDED.
            ok = wait_for(lambda: s.metrics().get(
                'femsimp_jobs_total{status="DEADLINE_EXCEEDED"}', 0) > before, 30, 0.2)
            if not ok:
                self.finding(name, "femsimp_jobs_total{status=DEADLINE_EXCEEDED} + 1 within "
                             "--result_idle_seconds 3 (+ slack)", "no change in 30 s")
            info = self.wait_terminal(name, s, j.job_id)
            # The engine's work succeeded; the record says the result was not delivered.
            if info and (info.state != pb2.JOB_STATE_SUCCEEDED or
                         info.status_code != "DEADLINE_EXCEEDED" or
                         "result not delivered" not in info.status_message):
                self.finding(name, "job SUCCEEDED, DEADLINE_EXCEEDED 'result not delivered: ...'",
                             f"{pb2.JobState.Name(info.state)} {info.status_code} "
                             f"{info.status_message!r}")
            c.cancel()
            c.wait()
            channel.close()

        self.case("a result nobody reads", unread_result)

        def tenant_limit(name):
            a = self.auth
            jobs = [self.start_slow(a, "tenant-a", tenant="a", wait_running=False)
                    for _ in range(2)]
            self.expect_stream(name, a, Gate([slow_spec("third")]), SC.RESOURCE_EXHAUSTED,
                               ["max_jobs_per_tenant"], tenant="a")
            # Tenant b is not locked out by a's jobs: admitted (a's may hold both workers, so b's
            # job may wait in the queue until they are cancelled below).
            b = Call(a.stub, [spec_msg(label="tenant-b")] + chunks(S), timeout=30,
                     metadata=a.md("b"))
            if not b.accepted.wait(10) or not b.job_id:
                self.finding(name + ": the other tenant", "Accepted", f"{b.code} {b.details}")
            for c in jobs:
                a.stub.CancelJob(pb2.CancelJobRequest(job_id=c.job_id), timeout=10,
                                 metadata=a.md("a"))
                c.wait()
                self.check_status(name + ": cancelled", c.code, c.details, SC.CANCELLED)
                self.wait_terminal(name, a, c.job_id, tenant="a", want_code="CANCELLED")
            self.check_status(name + ": the other tenant", b.wait(), b.details, SC.OK)

        self.case("per-tenant limit (--max_jobs_per_tenant 2)", tenant_limit)

        def metrics_idle(name, n_idle, n_half, bound):
            socks = []
            for i in range(n_idle + n_half):
                k = socket.create_connection(("127.0.0.1", s.metrics_port), timeout=5)
                if i >= n_idle:
                    k.sendall(b"GET /metrics HTTP/1.1\r\nHost: x\r\n")  # never finished
                socks.append(k)
            time.sleep(0.2)
            t0 = time.monotonic()
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{s.metrics_port}/metrics",
                                            timeout=10) as r:
                    r.read()
                took = time.monotonic() - t0
                if took > bound:
                    self.finding(name, f"GET /metrics answered within {bound} s", f"{took:.2f} s")
            except OSError as e:
                self.finding(name, f"GET /metrics answered within {bound} s", f"{e}")
            for k in socks:
                k.close()

        # The responder serves from one epoll loop (server/metrics_http.h): no number of idle
        # or half-sent connections delays a scrape, beyond its 256 kept connections too (the
        # oldest are dropped).
        self.case("4 idle + 3 half-request connections to /metrics", metrics_idle, 4, 3, 1.0)
        self.case("150 idle + 150 half-request connections to /metrics", metrics_idle, 150, 150,
                  1.0)

    # 4. Every admitted job ends ------------------------------------------------------------
    def job_ends(self):
        s = self.main
        M = MEDIUM

        def cancel_mid_upload(name):
            gate = Gate([spec_msg(M, label="mid-upload")] + chunks(M)[:1])
            c = Call(s.stub, gate, timeout=30)
            c.accepted.wait(10)
            c.cancel()
            gate.release.set()
            c.wait()
            self.check_status(name, c.code, c.details, SC.CANCELLED)
            if c.job_id:
                self.job_ids.append(c.job_id)
                self.wait_terminal(name, s, c.job_id, want_code="CANCELLED")

        self.case("client cancels mid-upload", cancel_mid_upload)

        def canceljob_running(name):
            c = self.start_slow(s, "canceljob")
            r = s.stub.CancelJob(pb2.CancelJobRequest(job_id=c.job_id), timeout=10)
            if r.previous_state != pb2.JOB_STATE_RUNNING:
                self.finding(name, "previous_state RUNNING", pb2.JobState.Name(r.previous_state))
            c.wait()
            self.check_status(name, c.code, c.details, SC.CANCELLED, ["CancelJob"])
            self.wait_terminal(name, s, c.job_id, want_code="CANCELLED")
            r = s.stub.CancelJob(pb2.CancelJobRequest(job_id=c.job_id), timeout=10)
            if r.previous_state != pb2.JOB_STATE_CANCELLED:
                self.finding(name + " (again)", "previous_state CANCELLED",
                             pb2.JobState.Name(r.previous_state))

        self.case("CancelJob while running", canceljob_running)

        def canceljob_queued(name):
            running = [self.start_slow(s, f"busy{i}") for i in range(2)]
            q = self.start_slow(s, "queued", wait_running=False)
            ok = wait_for(lambda: s.get_job(q.job_id).state == pb2.JOB_STATE_QUEUED, 10)
            if not ok:
                self.finding(name, "the third job QUEUED behind 2 workers",
                             pb2.JobState.Name(s.get_job(q.job_id).state))
            r = s.stub.CancelJob(pb2.CancelJobRequest(job_id=q.job_id), timeout=10)
            if r.previous_state != pb2.JOB_STATE_QUEUED:
                self.finding(name, "previous_state QUEUED", pb2.JobState.Name(r.previous_state))
            q.wait()
            self.check_status(name, q.code, q.details, SC.CANCELLED)
            self.wait_terminal(name, s, q.job_id, want_code="CANCELLED")
            for c in running:
                c.cancel()
            for c in running:
                c.wait()
                self.wait_terminal(name + " (dropped)", s, c.job_id, want_code="CANCELLED")

        self.case("CancelJob while queued; dropped calls while running", canceljob_queued)

        def drop_call(name):
            c = self.start_slow(s, "dropped")
            c.cancel()
            c.wait()
            self.check_status(name, c.code, c.details, SC.CANCELLED)
            self.wait_terminal(name, s, c.job_id, want_code="CANCELLED")

        self.case("client drops the call while running", drop_call)

        def deadline(name):
            c = Call(s.stub, [slow_spec("deadline")] + chunks(M), timeout=3)
            c.wait()
            self.check_status(name, c.code, c.details, SC.DEADLINE_EXCEEDED)
            if c.job_id:
                self.job_ids.append(c.job_id)
                self.wait_terminal(name, s, c.job_id, want_code="DEADLINE_EXCEEDED")
            else:
                self.finding(name, "an Accepted job", "none")

        self.case("client deadline while running", deadline)

        def killed_client(name, when):
            p = subprocess.Popen([sys.executable, os.path.abspath(__file__), "--child",
                                  str(s.port), when], stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, text=True)
            line = p.stdout.readline().strip()
            if not re.fullmatch(r"[0-9a-f]{32}", line):
                p.kill()
                self.finding(name, "the child's job id", f"'{line}' {p.stderr.read()[:300]}")
                return
            self.job_ids.append(line)
            if when == "running" and not wait_for(lambda: s.get_job(line).passes_started > 0, 20):
                self.finding(name, "the child's job RUNNING", pb2.JobState.Name(
                    s.get_job(line).state))
            p.send_signal(signal.SIGKILL)
            p.wait()
            self.wait_terminal(name, s, line, timeout=30)

        self.case("client process SIGKILLed while running", killed_client, "running")
        self.case("client process SIGKILLed mid-upload", killed_client, "upload")

    # 5. Cross-client / security ------------------------------------------------------------
    def security(self):
        a = self.auth
        UN = SC.UNAUTHENTICATED
        wrong = (("authorization", "Bearer not-a-token-" + "z" * 20),)
        for label, md in (("no token", None), ("wrong token", wrong),
                          ("token without Bearer", (("authorization", self.tokens["a"]),)),
                          ("Bearer with an empty token", (("authorization", "Bearer "),))):
            for method, call in (
                    ("Simplify", lambda md: self.expect_stream_md(a, md)),
                    ("GetJob", lambda md: self._unary(a.stub.GetJob,
                                                      pb2.GetJobRequest(job_id="0" * 32), md)),
                    ("CancelJob", lambda md: self._unary(a.stub.CancelJob,
                                                         pb2.CancelJobRequest(job_id="0" * 32),
                                                         md)),
                    ("ListJobs", lambda md: self._unary(a.stub.ListJobs, pb2.ListJobsRequest(),
                                                        md)),
                    ("ServerInfo", lambda md: self._unary(a.stub.ServerInfo,
                                                          pb2.ServerInfoRequest(), md))):
                def run(n, call=call, md=md):
                    code, details = call(md)
                    if self.check_status(n, code, details, UN, ["token", "authorization"]):
                        for t in (self.tokens["a"], self.tokens["b"], "not-a-token"):
                            if t in details:
                                self.finding(n, "the token not echoed", f"'{details}'")
                self.case(f"{method}: {label}", run)

        def cross_tenant(name):
            b = self.start_slow(a, "tenant-b-job", tenant="b")
            self.expect_unary(name + ": GetJob", a.stub.GetJob, pb2.GetJobRequest(job_id=b.job_id),
                              SC.NOT_FOUND, ["no job"], metadata=a.md("a"))
            self.expect_unary(name + ": CancelJob", a.stub.CancelJob,
                              pb2.CancelJobRequest(job_id=b.job_id), SC.NOT_FOUND, ["no job"],
                              metadata=a.md("a"))
            if a.get_job(b.job_id, "b").state != pb2.JOB_STATE_RUNNING:
                self.finding(name, "b's job still RUNNING after a's CancelJob",
                             pb2.JobState.Name(a.get_job(b.job_id, "b").state))
            listed = a.stub.ListJobs(pb2.ListJobsRequest(include_finished=True), timeout=10,
                                     metadata=a.md("a")).jobs
            if any(j.job_id == b.job_id for j in listed):
                self.finding(name, "a's ListJobs without b's job", "b's job listed")
            own = a.stub.ListJobs(pb2.ListJobsRequest(), timeout=10, metadata=a.md("b")).jobs
            if not any(j.job_id == b.job_id for j in own):
                self.finding(name, "b's ListJobs with b's job", "not listed")
            a.stub.CancelJob(pb2.CancelJobRequest(job_id=b.job_id), timeout=10, metadata=a.md("b"))
            b.wait()
            self.wait_terminal(name, a, b.job_id, tenant="b", want_code="CANCELLED")

        self.case("tenant a reads and cancels tenant b's job", cross_tenant)
        self.stats[self.family]["cases"] += 1  # the two NOT_FOUND checks count as cases too

        def huge_id(name, server, size, tenant=None):
            jid = "f" * size
            for method, fn, req in (("GetJob", server.stub.GetJob, pb2.GetJobRequest(job_id=jid)),
                                    ("CancelJob", server.stub.CancelJob,
                                     pb2.CancelJobRequest(job_id=jid))):
                try:
                    fn(req, timeout=10, metadata=server.md(tenant))
                    code, details = SC.OK, ""
                except grpc.RpcError as e:
                    code, details = e.code(), e.details() or ""
                if code not in (SC.NOT_FOUND, SC.INVALID_ARGUMENT):
                    self.finding(f"{name} ({method})", "NOT_FOUND or INVALID_ARGUMENT", code.name)
                else:
                    self.check_status(f"{name} ({method})", code, details, code, ["job_id", "job"])
                    if "f" * 100 in details:
                        self.finding(f"{name} ({method})", "the id not echoed", details[:100])

        self.case("GetJob/CancelJob with a 1 MiB job id", huge_id, a, 1 << 20, "a")
        self.case("GetJob/CancelJob with a 200 KiB job id", huge_id, self.main, 200 << 10)
        self.case("GetJob with control characters in the id",
                  lambda n: self.expect_unary(n, self.main.stub.GetJob,
                                              pb2.GetJobRequest(job_id="ab\x1b[2J\ncd"),
                                              SC.INVALID_ARGUMENT, ["job_id"]))
        self.case("GetJob of an unknown well-formed id",
                  lambda n: self.expect_unary(n, self.main.stub.GetJob,
                                              pb2.GetJobRequest(job_id="0" * 32),
                                              SC.NOT_FOUND, ["no job"]))

        def ids(name):
            seen = list(dict.fromkeys(self.job_ids))
            if len(seen) < 10:
                self.finding(name, "at least 10 job ids seen", str(len(seen)))
                return
            bad = [i for i in seen if not re.fullmatch(r"[0-9a-f]{32,}", i)]
            if bad:
                self.finding(name, "ids of >= 32 hex digits (128 bits)", str(bad[:3]))
            if len(set(self.job_ids)) != len(seen):
                self.finding(name, "distinct ids", "a repeat")
            nums = [int(i, 16) for i in seen if re.fullmatch(r"[0-9a-f]+", i)]
            close = [(x, y) for x, y in zip(nums, nums[1:]) if abs(x - y) < 2 ** 64]
            if close:
                self.finding(name, "ids not sequential or close", f"{len(close)} close pairs")
            # Every hex digit appears at roughly its share: no fixed or counter-like part.
            for pos in range(32):
                column = {i[pos] for i in seen}
                if len(column) == 1:
                    self.finding(name, "every digit position varying", f"position {pos} fixed")
                    break

        self.case("job ids look random", ids)

        def reflection(name):
            for svc in ("grpc.reflection.v1alpha.ServerReflection",
                        "grpc.reflection.v1.ServerReflection"):
                fn = self.main.channel.stream_stream(f"/{svc}/ServerReflectionInfo",
                                                     request_serializer=None,
                                                     response_deserializer=None)
                try:
                    list(fn(iter([b"\x3a\x00"]), timeout=10))  # list_services
                    code = SC.OK
                except grpc.RpcError as e:
                    code = e.code()
                if code != SC.UNIMPLEMENTED:
                    self.finding(f"{name} ({svc})", "UNIMPLEMENTED (reflection off by default)",
                                 code.name)

        self.case("reflection off by default", reflection)

        def refuses_to_start(name, args, words, want_rc=3):
            p = subprocess.run([os.path.join(self.build, "server", "femsimp-server"), *args],
                               capture_output=True, text=True, timeout=30)
            if p.returncode != want_rc:
                self.finding(name, f"exit {want_rc}", f"exit {p.returncode}: {p.stderr[-300:]}")
            elif not any(w in p.stderr for w in words):
                self.finding(name, f"a message naming {' or '.join(words)}", p.stderr[-300:])

        self.case("plaintext on 0.0.0.0 without --plaintext_remote", refuses_to_start,
                  [f"--listen=0.0.0.0:{free_port()}", "--metrics_listen="],
                  ["--plaintext_remote"])
        self.case("second server on a taken port", refuses_to_start,
                  [f"--listen=127.0.0.1:{self.main.port}", "--metrics_listen="],
                  ["cannot listen"])
        self.case("second server on a taken metrics port", refuses_to_start,
                  [f"--listen=127.0.0.1:{free_port()}",
                   f"--metrics_listen=127.0.0.1:{self.main.metrics_port}"], ["metrics", "9"])

        def forged_log_line(name):
            label = "probe\nFORGED job 0 end: OK\x1b[31m\rred\x07"
            c = Call(self.main.stub, [spec_msg(label=label, ratio=0.5)] + chunks(SMALL))
            c.wait()
            self.check_status(name, c.code, c.details, SC.OK)
            self.job_ids.append(c.job_id)
            time.sleep(0.2)
            log = open(self.main.log_path, "rb").read()
            lines = log.split(b"\n")
            if any(line.startswith(b"FORGED") for line in lines):
                self.finding(name, "no line starting with the label's text", "a forged line")
            if b"\x1b" in log or b"\r" in log or b"\x07" in log:
                self.finding(name, "no raw control bytes in the log", "ESC/CR/BEL found")
            mine = [line for line in lines if c.job_id.encode() in line and b"label=" in line]
            if not mine or b"\\x0a" not in mine[0]:
                self.finding(name, "the label escaped (\\x0a) on the job's start line",
                             repr(mine[:1]))
            for line in lines:
                if line and not re.match(rb"^\d{4}-\d\d-\d\dT", line):
                    self.finding(name, "every log line starting with a timestamp",
                                 repr(line[:120]))
                    break

        self.case("client label with a newline and escape bytes", forged_log_line)

    def expect_stream_md(self, server, md):
        c = Call(server.stub, [spec_msg()] + chunks(SMALL), timeout=20, metadata=md)
        c.wait()
        return c.code, c.details

    def _unary(self, fn, req, md):
        try:
            fn(req, timeout=10, metadata=md)
            return SC.OK, ""
        except grpc.RpcError as e:
            return e.code(), e.details() or ""

    # 6. Signals ----------------------------------------------------------------------------
    def signals(self):
        def sigterm(name):
            sv = Server(self, "sigterm", ["--workers=2", "--queue_capacity=4",
                                          "--threads_per_job=1", "--grace_period_seconds=3"])
            running = [self.start_slow(sv, f"term{i}") for i in range(2)]
            queued = self.start_slow(sv, "term-queued", wait_running=False)
            self.note("jobs running")
            t0 = time.monotonic()
            sv.proc.send_signal(signal.SIGTERM)
            # New calls get UNAVAILABLE while the grace period runs.
            time.sleep(0.3)
            c = Call(sv.stub, [spec_msg()] + chunks(SMALL), timeout=10)
            c.wait()
            self.check_status(name + ": a new call", c.code, c.details, SC.UNAVAILABLE,
                              ["shutting down", "shut down"])
            self.note("new call answered")
            for r in running:
                r.wait(20)
                self.note("running job ended")
                self.check_status(name + ": a running job", r.code, r.details, SC.UNAVAILABLE,
                                  ["grace period", "shut"])
            queued.wait(20)
            self.check_status(name + ": a queued job", queued.code, queued.details,
                              SC.UNAVAILABLE, ["shut"])
            self.note("queued job ended")
            try:
                rc = sv.proc.wait(timeout=20)
                self.note("server exited")
            except subprocess.TimeoutExpired:
                rc = None
                sv.proc.kill()
            took = time.monotonic() - t0
            if rc != 0:
                self.finding(name, "exit 0", f"exit {rc}")
            # The jobs are cancelled at 3 s; their handlers return at once, so the server is
            # gone soon after (it waited out a 5 s shutdown deadline for idle connections once).
            if took > 3 + 2.5:
                self.finding(name, "exit within the grace period (3 s) + 2.5 s", f"{took:.1f} s")
            sv.channel.close()
            sv.log.close()
            self.signal_port = sv.port

        self.case("SIGTERM with jobs running and queued", sigterm)
        self.stats[self.family]["cases"] += 3  # new call, running jobs, queued job

        def sigkill_restart(name):
            sv = Server(self, "sigkill", ["--workers=1", "--threads_per_job=1"],
                        port=getattr(self, "signal_port", None))
            self.note("server started")
            c = self.start_slow(sv, "killed")
            self.note("job running")
            sv.proc.send_signal(signal.SIGKILL)
            sv.proc.wait()
            c.wait(20)
            self.note("call ended")
            if c.code != SC.UNAVAILABLE:
                self.finding(name + ": the running call", "UNAVAILABLE", f"{c.code}")
            sv.channel.close()
            sv.log.close()
            sv.start()  # same port, at once
            self.note("restarted")
            self.servers.append(sv)
            d = Call(sv.stub, [spec_msg(ratio=0.5)] + chunks(SMALL))
            self.check_status(name + ": a job after the restart", d.wait(), d.details, SC.OK)
            sv.baseline = None

        self.case("SIGKILL, then a restart on the same port", sigkill_restart)

    # 7. CLI with bad files -----------------------------------------------------------------
    def cli(self):
        cli = os.path.join(self.build, "client", "femsimp")
        data = os.path.join(REPO, "tests", "data")
        d = os.path.join(self.work, "cli")
        os.makedirs(d)
        bases = []
        for src, ext in (("fandisk.off", "off"), ("fandisk.off", "obj"), ("fandisk.off", "stl"),
                         ("fandisk_groups_fields.ply", "ply"), ("fandisk_groups_fields.ply", "obj"),
                         ("fandisk.off", "msh")):
            out = os.path.join(d, f"base-{src.split('.')[0]}.{ext}")
            subprocess.run([cli, "simplify", os.path.join(data, src), out, "--ratio", "0.05",
                            "--threads", "1", "--quiet", "--drop-face-data"], check=True, capture_output=True,
                           timeout=60)
            bases.append(out)
        # Binary forms: STL as written by femsimp is binary? Make an ASCII STL and binary PLY too.
        stl_ascii = os.path.join(d, "base-ascii.stl")
        self._ascii_stl(os.path.join(d, "base-fandisk.off"), stl_ascii)
        bases.append(stl_ascii)
        rng = random.Random(self.seed + 7)
        ctrl = re.compile(rb"[\x00-\x08\x0b-\x1f\x7f]")
        per_base = 3 if self.quick else 20
        n_random = 2 if self.quick else 6

        def run_cli(name, path, expect_codes, want_where=True):
            outp = os.path.join(d, "out" + os.path.splitext(path)[1])
            try:
                p = subprocess.run([cli, "simplify", path, outp, "--threads", "1", "--quiet"],
                                   capture_output=True, timeout=20)
            except subprocess.TimeoutExpired:
                self.finding(name, "an exit within 20 s", "a hang")
                return
            rc = p.returncode
            self.cli_codes[rc] = self.cli_codes.get(rc, 0) + 1
            if rc < 0:
                self.finding(name, "an exit code", f"signal {-rc}")
                return
            if rc not in expect_codes:
                self.finding(name, f"exit in {sorted(expect_codes)}",
                             f"exit {rc}: {p.stderr[-300:]!r}")
            for stream, text in (("stdout", p.stdout), ("stderr", p.stderr)):
                if ctrl.search(text):
                    self.finding(name, f"no raw control bytes in {stream}",
                                 repr(ctrl.search(text).group()))
            err = p.stderr.decode(errors="replace")
            if rc == 3:
                shown = os.path.basename(path).encode("unicode_escape").decode()
                base = os.path.basename(path)
                if base not in err and shown not in err and not ctrl.search(base.encode()):
                    self.finding(name, "stderr naming the file", err[-300:])
                if want_where and not re.search(WHERE, err):
                    self.finding(name, "stderr naming the line or byte", err[-300:])
            if len(p.stderr) > 4096:
                self.finding(name, "a bounded stderr (<= 4 KiB)", f"{len(p.stderr)} bytes")

        readable = {0, 3, 4}  # documented: repaired and simplified, unreadable, invalid mesh
        for b in bases:
            raw = open(b, "rb").read()
            ext = os.path.splitext(b)[1]
            self.case(f"{os.path.basename(b)} as written", lambda n, b=b: run_cli(n, b, {0}))
            for k in range(per_base):
                kind = ["flip", "truncate", "insert", "control"][k % 4]
                buf = bytearray(raw)
                if kind == "flip":
                    for _ in range(rng.randint(1, 8)):
                        i = rng.randrange(len(buf))
                        buf[i] ^= 1 << rng.randrange(8)
                elif kind == "truncate":
                    buf = buf[:rng.randrange(1, len(buf))]
                elif kind == "insert":
                    i = rng.randrange(len(buf))
                    buf[i:i] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 40)))
                else:
                    i = rng.randrange(min(len(buf), 400))
                    buf[i:i] = b"\x1b[31m\x07\x00\x1b]0;title\x07"
                path = os.path.join(d, f"m{k}-{kind}-{os.path.basename(b)}")
                open(path, "wb").write(bytes(buf))
                self.case(f"{os.path.basename(b)} {kind} #{k}",
                          lambda n, path=path: run_cli(n, path, readable))
        for k in range(n_random):
            for ext in (".off", ".obj", ".stl", ".ply", ".msh"):
                path = os.path.join(d, f"random{k}{ext}")
                size = rng.choice([0, 1, 83, 84, 200, 5000])
                buf = bytes(rng.randrange(256) for _ in range(size))
                if ext == ".ply" and k % 2:
                    buf = b"ply\nformat binary_little_endian 1.0\n" + buf
                open(path, "wb").write(buf)
                # An empty or random file is unreadable (3); a random binary STL of 84+ bytes
                # may parse as facets (then repaired or refused: 0 or 4).
                codes = {3} if ext != ".stl" else readable
                self.case(f"random bytes ({size} B) as {ext}",
                          lambda n, path=path, codes=codes: run_cli(n, path, codes,
                                                                    want_where=size > 0))
        # Refusals that once lost their line: a NUL byte quoted from the file cut the message
        # (printf's %s), and two truncations named no line.
        for fname, content in (
                ("nul-section.msh", b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entit\x00\x1b[31mies\n"
                                    b"0 0 0 0\n$EndEntities\n"),
                ("nul-token.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\x00\x1b[2J\n0 1 0\n3 0 1 2\n"),
                ("cut-in-facet.stl", b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"
                                     b"   vertex 1 0 0\n"),
                ("no-end-header.ply", b"ply\nformat ascii 1.0\nelement vertex 3\n")):
            path = os.path.join(d, fname)
            open(path, "wb").write(content)
            self.case(f"{fname}: refused with its line", lambda n, path=path: run_cli(n, path, {3}))
        # Without 'endsolid' but every facet whole: read, with a warning (some writers leave it
        # out).
        path = os.path.join(d, "no-endsolid.stl")
        open(path, "wb").write(b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"
                               b"   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n")
        self.case("no-endsolid.stl: read", lambda n, path=path: run_cli(n, path, {0}))
        # A file name carrying control characters, with bad content.
        evil = os.path.join(d, "evil\x1b[2J\x07name\x1b]0;t\x07.off")
        open(evil, "wb").write(b"OFF\n3 1 0\n0 0 0\n1 0 \x1b[31mx\n0 1 0\n3 0 1 2\n")
        self.case("file name and content with escape sequences",
                  lambda n: run_cli(n, evil, {3}))
        self.case("missing file with escape sequences in its name",
                  lambda n: run_cli(n, os.path.join(d, "nope\x1b[31m.off"), {3},
                                    want_where=False))
        self.case("a directory as input", lambda n: run_cli(n, d + "/", {3}, want_where=False))

    def _ascii_stl(self, off_path, out):
        lines = open(off_path).read().split("\n")
        k = 0
        while not lines[k].strip() or lines[k].startswith("#") or lines[k].strip() == "OFF":
            k += 1
        nv, nf = map(int, lines[k].split()[:2])
        v = [lines[k + 1 + i].split() for i in range(nv)]
        with open(out, "w") as f:
            f.write("solid probe\n")
            for i in range(nf):
                ids = list(map(int, lines[k + 1 + nv + i].split()[1:4]))
                f.write(" facet normal 0 0 0\n  outer loop\n")
                for j in ids:
                    f.write(f"   vertex {' '.join(v[j])}\n")
                f.write("  endloop\n endfacet\n")
            f.write("endsolid probe\n")

    # After all: nothing held -----------------------------------------------------------------
    def leaks(self):
        for s in self.servers:
            if not s.alive():
                self.stats[self.family]["cases"] += 1
                if s.name not in ("sigterm",):
                    self.finding(f"{s.name}: alive", "running", f"exit {s.proc.returncode}")
                continue
            name = s.name

            def idle(n, s=s):
                busy = wait_for(lambda: not s.unfinished(), 30, 0.2)
                if not busy:
                    self.finding(n, "no job QUEUED or RUNNING",
                                 str([(j.job_id, pb2.JobState.Name(j.state))
                                      for j in s.unfinished()][:5]))
                ok = wait_for(lambda: (lambda m: m.get("femsimp_queue_depth", 0) == 0 and
                                       m.get("femsimp_running_jobs", 0) == 0 and
                                       m.get("femsimp_memory_admitted_bytes", 0) == 0)(
                                           s.metrics()), 30, 0.2)
                if not ok:
                    m = s.metrics()
                    self.finding(n, "queue depth, running jobs and admitted memory 0",
                                 f"{m.get('femsimp_queue_depth')} "
                                 f"{m.get('femsimp_running_jobs')} "
                                 f"{m.get('femsimp_memory_admitted_bytes')}")

            self.case(f"{name}: no job held, gauges 0", idle)
            if getattr(s, "baseline", None) is None:
                self.figures[name] = {"end": proc_figures(s.proc.pid)}
                continue
            base = s.baseline

            def released(n, s=s, base=base):
                slack = {"threads": 4, "fds": 4}
                end = wait_for(lambda: (lambda f: f if f["threads"] <= base["threads"] +
                                        slack["threads"] and f["fds"] <= base["fds"] +
                                        slack["fds"] else None)(proc_figures(s.proc.pid)),
                               20, 0.25) or proc_figures(s.proc.pid)
                self.figures[s.name] = {"baseline": base, "end": end}
                for k in ("threads", "fds"):
                    if end[k] > base[k] + slack[k]:
                        self.finding(n, f"{k} within {slack[k]} of the baseline {base[k]}",
                                     str(end[k]))
                # Under AddressSanitizer freed memory waits in its quarantine (up to 256 MiB), so
                # RSS says nothing of what the server holds (threads and fds still do).
                if not self.asan and end["rss_kib"] > base["rss_kib"] + 32 * 1024:
                    self.finding(n, f"RSS within 32 MiB of the baseline {base['rss_kib']} KiB",
                                 f"{end['rss_kib']} KiB")

            self.case(f"{name}: threads, fds, RSS back to the baseline", released)


def child(port, when):
    """--child PORT WHEN: starts a slow job, prints its id, and waits to be SIGKILLed."""
    channel = grpc.insecure_channel(f"127.0.0.1:{port}")
    stub = pb2_grpc.SimplifierStub(channel)
    if when == "running":  # the whole mesh, half-closed: the job queues and runs
        requests = iter([slow_spec("child")] + chunks(MEDIUM))
    else:  # the spec and one chunk, then a stall (killed before --upload_idle_seconds)
        requests = iter(Gate([slow_spec("child")] + chunks(MEDIUM)[:1]))
    for r in stub.Simplify(requests, timeout=120):
        if r.HasField("accepted"):
            print(r.accepted.job_id, flush=True)
    time.sleep(120)


def main():
    if len(sys.argv) >= 2 and sys.argv[1] == "--child":
        child(sys.argv[2], sys.argv[3])
        return 0
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(REPO, "build"))
    ap.add_argument("--quick", action="store_true", help="fewer garbage and CLI cases (< 60 s)")
    ap.add_argument("--seed", type=int, default=15)
    ap.add_argument("--json-out")
    ap.add_argument("--keep-work", action="store_true", help="keep the servers' logs and files")
    ap.add_argument("--verbose", action="store_true", help="print every case with its seconds")
    a = ap.parse_args()
    p = Probe(a)
    try:
        p.run()
    finally:
        for s in p.servers:
            if s.alive():
                s.proc.kill()
    print()
    print(f"{'family':<10} {'cases':>6} {'findings':>9} {'seconds':>8}")
    for f in FAMILIES:
        st = p.stats[f]
        print(f"{f:<10} {st['cases']:>6} {st['findings']:>9} {st['seconds']:>8}")
    total_cases = sum(st["cases"] for st in p.stats.values())
    rest = round(p.total_seconds - sum(st["seconds"] for st in p.stats.values()), 1)
    print(f"{'(servers started, warmed up and stopped)':<37} {rest:>8}")
    print(f"{'total':<10} {total_cases:>6} {len(p.findings):>9} {p.total_seconds:>8}")
    print()
    print("femsimp simplify exit codes over the cli cases: " +
          ", ".join(f"{k}: {v}" for k, v in sorted(p.cli_codes.items())))
    for name, fig in p.figures.items():
        b = fig.get("baseline")
        e = fig["end"]
        print(f"server {name}: " + (f"baseline threads {b['threads']} fds {b['fds']} RSS "
                                    f"{b['rss_kib'] / 1024:.1f} MiB -> " if b else "") +
              f"end threads {e['threads']} fds {e['fds']} RSS {e['rss_kib'] / 1024:.1f} MiB")
    if p.asan:
        print("AddressSanitizer build: RSS not compared with the baseline (its quarantine keeps "
              "freed memory)")
    if a.json_out:
        with open(a.json_out, "w") as f:
            json.dump({"stats": p.stats, "total_cases": total_cases, "findings": p.findings,
                       "seconds": p.total_seconds, "figures": p.figures, "quick": a.quick,
                       "cli_exit_codes": {str(k): v for k, v in sorted(p.cli_codes.items())},
                       "seed": a.seed}, f, indent=1)
    print(f"probe: {'PASSED' if not p.findings else 'FAILED'}: {total_cases} cases, "
          f"{len(p.findings)} findings in {p.total_seconds} s"
          + (f" (work dir {p.work})" if a.keep_work or p.findings else ""))
    if not a.keep_work and not p.findings:
        import shutil
        shutil.rmtree(p.work, ignore_errors=True)
    return 0 if not p.findings else 1


if __name__ == "__main__":
    sys.exit(main())
