"""Client: femsimp's gRPC service from Python, with the C++ client's retries and deadlines
(client/retry.h): a job that ends UNAVAILABLE, or RESOURCE_EXHAUSTED with a retry pushback
(queue full), is sent again after the pushback or a backoff (0.25 s doubling up to 8 s, +-20 %);
the deadline bounds all attempts together. A job counts as done only once its Result and all
its chunks arrived and add up, so sending it again is safe.
"""
import logging
import math
import random
import sys
import threading
import time
import warnings
from dataclasses import dataclass, field

import grpc

from . import _wire, options as opts
from ._stubs import load as _load_stubs
from .errors import FemsimpError, FemsimpWarning
from .inputs import prepare
from .progress import ProgressBar

_log = logging.getLogger("femsimp")
_LABEL_BYTES = 128


@dataclass
class Pass:
    """One simplification pass of a job, as the server streams it."""
    job_id: str
    number: int             # 1-based
    vertices_left: int
    removed: int
    tried: int
    rejections: dict        # criterion -> candidates refused by it
    seconds: float
    message: object = field(repr=False, default=None)  # the femsimp.v1.Progress


@dataclass
class Outcome:
    """A finished job: the output (the input's kind), the server's Result, the passes."""
    mesh: object
    result: object          # femsimp.v1.Result: sizes, timings, stop reason, fidelity figures
    job_id: str
    passes: list
    attempts: int
    repair: object = None   # femsimp.v1.RepairReport of the upload, when the server sent one


@dataclass
class Job:
    """A job in the server's list (femsimp.v1.JobInfo)."""
    job_id: str
    label: str
    state: str              # QUEUED, RUNNING, SUCCEEDED, FAILED, CANCELLED
    queue_position: int
    passes_done: int
    input_vertices: int
    input_faces: int
    vertices_left: int
    status_code: str
    status_message: str


@dataclass
class RetryPolicy:
    """client/retry.h RetryPolicy."""
    max_attempts: int = 5
    initial_backoff: float = 0.25
    max_backoff: float = 8.0
    multiplier: float = 2.0
    jitter: float = 0.2


def is_retryable(code, pushback_ms):
    """UNAVAILABLE always; RESOURCE_EXHAUSTED only with a pushback >= 0 (queue full): without one
    it is a size limit that fails the same way every time."""
    if code == grpc.StatusCode.UNAVAILABLE:
        return True
    return code == grpc.StatusCode.RESOURCE_EXHAUSTED and pushback_ms is not None \
        and pushback_ms >= 0


def retry_delay(policy, failed_attempt, pushback_ms, unit):
    """Seconds to wait after attempt `failed_attempt` (from 1) failed: the server's pushback,
    lengthened by up to `jitter`, or the jittered exponential backoff. unit: uniform in [0, 1)."""
    jitter = min(1.0, max(0.0, policy.jitter))
    if pushback_ms is not None and pushback_ms >= 0:
        return math.ceil(pushback_ms * (1 + jitter * unit)) / 1000.0
    backoff = policy.initial_backoff * max(1.0, policy.multiplier) ** max(0, failed_attempt - 1)
    return min(backoff, policy.max_backoff) * (1 - jitter + 2 * jitter * unit)


class _Failed(Exception):
    def __init__(self, code, details, pushback_ms=None, job_id=""):
        super().__init__(details)
        self.code, self.details, self.pushback_ms, self.job_id = code, details, pushback_ms, job_id


def _warn_if_crossing(result, allowed):
    """The C++ CLI's warning: a mesher refuses an output whose faces cross (Result
    .output_crossings counts the pairs that certainly do)."""
    c = result.output_crossings
    o = c.overlaps
    if o.pairs > 0:
        at = ", ".join(f"{x:.6g}" for x in o.at)
        source = ("from the input or the run (allow_self_intersections)" if allowed
                  else "kept from the input (the simplification makes none)")
        warnings.warn(f"the output has overlapping faces: {o.pairs} face pair"
                      f"{'' if o.pairs == 1 else 's'} overlap in their plane, over an area of "
                      f"{o.area:.6g} (the first: faces {o.face_a} and {o.face_b}, at ({at})): "
                      f"bodies exported apart that touch, each with its own triangulation of "
                      f"the contact; {source}; tetgen and most FE meshers refuse overlapping "
                      f"faces (imprint=True makes each planar contact one surface shared by "
                      f"the bodies)", FemsimpWarning, stacklevel=3)
    f = c.folds
    if f.pairs > 0:
        at = ", ".join(f"{x:.6g}" for x in f.at)
        source = ("from the input or the run (allow_self_intersections)" if allowed
                  else "kept from the input, where no flip of their edge unfolds them (the "
                       "repair records' fold_left say why)")
        warnings.warn(f"the output has folded faces: {f.pairs} face pair"
                      f"{'' if f.pairs == 1 else 's'} lie on each other in their plane, one of "
                      f"each turned over (the first: faces {f.face_a} and {f.face_b}, along "
                      f"their common edge at ({at})); {source}; tetgen and most FE meshers "
                      f"refuse faces lying on each other", FemsimpWarning, stacklevel=3)
    if c.pairs == 0:
        return
    at = ", ".join(f"{x:.6g}" for x in c.at)
    cause = ("allow_self_intersections let the run make crossings" if allowed
             else "the input's own crossings, kept (the simplification makes none)")
    if c.cut_short:  # a soup of facets: the check stopped counting
        what = (f"at least {c.pairs} face pairs cross (the check stopped there: a soup of "
                f"facets, or bodies exported overlapping; the first it found: faces {c.face_a} "
                f"and {c.face_b}, at ({at}))")
    else:
        what = (f"{c.pairs} face pair{'' if c.pairs == 1 else 's'} cross (the first: faces "
                f"{c.face_a} and {c.face_b}, at ({at}))")
    warnings.warn(f"the output intersects itself: {what}; {cause}; a mesher such as tetgen "
                  f"refuses it (unite_overlaps=True replaces closed bodies exported overlapping "
                  f"by their union)", FemsimpWarning, stacklevel=3)


def _warn_if_open(result):
    """The C++ CLI lists the openings repair left (a face missing): tetgen refuses the output."""
    left = result.repair.counts.get("hole_left", 0)
    if left == 0:
        return
    first = next((r for r in result.repair.records if r.kind == "hole_left"), None)
    where = (f" (the first at ({', '.join(f'{x:.6g}' for x in first.at)}): {first.detail})"
             if first is not None else "")
    warnings.warn(f"the surface is open: repair left {left} hole{'' if left == 1 else 's'} "
                  f"open{where}; tetgen and solid FE models need a closed surface "
                  f"(fill_holes='planar' closes a solid's openings that lie in one plane)",
                  FemsimpWarning, stacklevel=3)


def _warn_if_shared_shell(result):
    """A body inside another that shares its whole surface with it is left out of the mass."""
    left = result.repair.counts.get("shared_shell_left", 0)
    if left == 0:
        return
    first = next((r for r in result.repair.records if r.kind == "shared_shell_left"), None)
    where = f" (the first: {first.detail})" if first is not None else ""
    warnings.warn(f"{left} closed surface{'' if left == 1 else 's'} two bodies share kept as a "
                  f"cavity's wall{where}; the volume, the moments and the mass budgets leave the "
                  f"body inside out", FemsimpWarning, stacklevel=3)


class Client:
    """A connection to a femsimp-server.

    address: "host:port" (or any gRPC target, e.g. dns:///name:port: calls are spread over every
    address with round_robin). token: sent as "authorization: Bearer TOKEN" on every call.
    tls: None (plaintext), True (TLS with the system's roots), a path to a PEM root certificate,
    or grpc.ChannelCredentials. max_attempts: calls per job (1: no retry). deadline: seconds a
    simplify() may take in all, attempts included (None: no limit). progress_bar: draw a bar on
    stderr per pass (None: when stderr is a terminal).
    """

    def __init__(self, address, token=None, tls=None, max_attempts=5, deadline=None,
                 progress_bar=None):
        if max_attempts < 1:
            raise ValueError(f"max_attempts = {max_attempts}: must be at least 1")
        self.address = address
        self.policy = RetryPolicy(max_attempts=max_attempts)
        self.deadline = deadline
        self.progress_bar = progress_bar
        self._pb2, pb2_grpc = _load_stubs()
        channel_options = [
            ("grpc.max_receive_message_length", 64 << 20),
            # Reconnect about as soon as a retry comes back (remote_call.cc MakeChannel).
            ("grpc.initial_reconnect_backoff_ms", 250),
            ("grpc.max_reconnect_backoff_ms", 8000),
            ("grpc.lb_policy_name", "round_robin"),
        ]
        if tls is None or tls is False:
            self._channel = grpc.insecure_channel(address, options=channel_options)
        else:
            if isinstance(tls, grpc.ChannelCredentials):
                creds = tls
            elif tls is True:
                creds = grpc.ssl_channel_credentials()
            else:
                with open(tls, "rb") as f:
                    creds = grpc.ssl_channel_credentials(root_certificates=f.read())
            self._channel = grpc.secure_channel(address, creds, options=channel_options)
        self._metadata = (("authorization", f"Bearer {token}"),) if token else ()
        self._stub = pb2_grpc.SimplifierStub(self._channel)
        self._simplify = self._channel.stream_stream(
            "/femsimp.v1.Simplifier/Simplify", request_serializer=None,
            response_deserializer=_wire.response_deserializer(self._pb2))
        self._lock = threading.Lock()
        self._calls = set()
        self._cancelled = False

    def close(self):
        """Closes the channel; running calls end CANCELLED."""
        self._channel.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # Unary calls.

    def _unary(self, method, request, timeout):
        try:
            return method(request, timeout=timeout, metadata=self._metadata)
        except grpc.RpcError as e:
            raise FemsimpError(e.code(), e.details() or "", self.address) from None

    def server_info(self, timeout=10):
        """The server's version, back ends, limits and queue (femsimp.v1.ServerInfoResponse)."""
        return self._unary(self._stub.ServerInfo, self._pb2.ServerInfoRequest(), timeout)

    def jobs(self, include_finished=True, timeout=10):
        """Queued, running and (include_finished) recently finished jobs, newest first."""
        resp = self._unary(self._stub.ListJobs,
                           self._pb2.ListJobsRequest(include_finished=include_finished), timeout)
        return [Job(j.job_id, j.client_label, self._pb2.JobState.Name(j.state)[len("JOB_STATE_"):],
                    j.queue_position, j.passes_done, j.input_vertices, j.input_faces,
                    j.vertices_left, j.status_code, j.status_message) for j in resp.jobs]

    def cancel(self, job_id=None, timeout=10):
        """Cancels a job. With a job id: CancelJob on the server (any client's job), returning
        the state it had (QUEUED or RUNNING were cancelled; finished ones are unchanged); its
        Simplify call ends CANCELLED. Without: this client's running simplify() calls, which
        raise FemsimpError(CANCELLED) and are not retried."""
        if job_id is None:
            with self._lock:
                self._cancelled = True
                calls = list(self._calls)
            for call in calls:
                call.cancel()
            return None
        resp = self._unary(self._stub.CancelJob, self._pb2.CancelJobRequest(job_id=job_id),
                           timeout)
        return self._pb2.JobState.Name(resp.previous_state)[len("JOB_STATE_"):]

    # Simplify.

    def simplify(self, mesh, progress=None, output=None, strict=False, deadline=None,
                 label=None, **options):
        """Simplifies `mesh` on the server; returns the same kind of mesh (inputs.py).

        mesh: a SurfaceMesh, (points, triangles[, groups[, fields]]) numpy arrays, a
        meshio.Mesh, or a path meshio reads (then output= is the path to write, returned).
        progress: called with a Pass after every pass. strict: refuse (MeshError) cells and data
        femsimp does not simplify instead of leaving them out with a FemsimpWarning.
        deadline: seconds for the whole job (default: the client's). label: the job's name in
        the server's list. options: the engine's (femsimp.OPTIONS), e.g. tolerance_relative=0.005,
        cost="quadric", cell_spes=4; unknown or out of range: OptionError before any upload.
        Failures raise FemsimpError with the gRPC status code and the server's message."""
        return self.run(mesh, progress=progress, output=output, strict=strict,
                        deadline=deadline, label=label, **options).mesh

    def run(self, mesh, progress=None, output=None, strict=False, deadline=None, label=None,
            **options):
        """simplify(), returning the whole Outcome (mesh, Result, passes, attempts)."""
        checked = opts.check(options)
        prepared = prepare(mesh, strict=strict, output=output)
        surface = prepared.surface
        spec = self._pb2.JobSpec(vertex_count=surface.num_points,
                                 face_count=surface.num_triangles,
                                 has_face_groups=surface.groups is not None,
                                 face_field_names=list(surface.fields),
                                 origin=list(surface.origin) if any(surface.origin) else [],
                                 client_label=_truncate(label or prepared.label))
        opts.to_proto(checked, spec.options)
        requests = [self._pb2.SimplifyRequest(spec=spec).SerializeToString()]
        requests += _wire.encode_chunks(surface)

        bar = None
        show = self.progress_bar if self.progress_bar is not None else sys.stderr.isatty()
        if show:
            bar = ProgressBar(surface.num_points, checked.get("ratio", 0.0),
                              checked.get("target_vertices", 0))
        deadline = self.deadline if deadline is None else deadline
        deadline_at = time.monotonic() + deadline if deadline else None
        with self._lock:
            self._cancelled = False
        try:
            outcome = self._with_retry(requests, progress, bar, deadline_at)
        finally:
            if bar:
                bar.close()
        points, triangles, groups, fields = outcome.mesh
        if tuple(outcome.result.origin or (0.0, 0.0, 0.0)) != tuple(surface.origin):
            raise FemsimpError(grpc.StatusCode.DATA_LOSS,
                               f"malformed result: origin {list(outcome.result.origin)}, the job "
                               f"was sent with {list(surface.origin)}", self.address,
                               job_id=outcome.job_id)
        outcome.mesh = prepared.restore(points, triangles, groups, fields)
        _warn_if_crossing(outcome.result, checked.get("allow_self_intersections", False))
        _warn_if_open(outcome.result)
        _warn_if_shared_shell(outcome.result)
        return outcome

    def _with_retry(self, requests, progress, bar, deadline_at):
        for attempt in range(1, self.policy.max_attempts + 1):
            timeout = None
            if deadline_at is not None:
                timeout = max(0.0, deadline_at - time.monotonic())
            try:
                outcome = self._attempt(requests, progress, bar, timeout)
                outcome.attempts = attempt
                return outcome
            except _Failed as f:
                failed = f
            note = ""
            with self._lock:
                cancelled = self._cancelled
            if cancelled or not is_retryable(failed.code, failed.pushback_ms):
                pass
            elif attempt >= self.policy.max_attempts:
                if attempt > 1:
                    note = f" (gave up after {attempt} attempts)"
            else:
                delay = retry_delay(self.policy, attempt, failed.pushback_ms, random.random())
                if deadline_at is not None and time.monotonic() + delay >= deadline_at:
                    note = f" (attempt {attempt}; no time left to retry before the deadline)"
                else:
                    line = (f"femsimp: attempt {attempt} of {self.policy.max_attempts} failed "
                            f"({failed.code.name}: {failed.details}); retrying in {delay:.1f} s")
                    bar.note(line) if bar else _log.warning(line)
                    time.sleep(delay)
                    if failed.code == grpc.StatusCode.UNAVAILABLE:
                        self._reconnect(delay, deadline_at)
                    continue
            raise FemsimpError(failed.code, failed.details + note, self.address,
                               failed.pushback_ms, attempt, failed.job_id) from None

    def _reconnect(self, wait, deadline_at):
        """After UNAVAILABLE: ask the channel to connect now and give it up to one more backoff,
        so the next attempt finds a replica that is back (retry.cc)."""
        if deadline_at is not None:
            wait = min(wait, max(0.0, deadline_at - time.monotonic()))
        try:
            grpc.channel_ready_future(self._channel).result(timeout=wait)
        except grpc.FutureTimeoutError:
            pass

    def _attempt(self, requests, progress, bar, timeout):
        pb2 = self._pb2
        with self._lock:
            if self._cancelled:
                raise _Failed(grpc.StatusCode.CANCELLED, "cancelled by the client")
            call = self._simplify(iter(requests), timeout=timeout, metadata=self._metadata)
            self._calls.add(call)
        job_id, result, repair, assembler, malformed = "", None, None, None, None
        passes = []
        try:
            for resp in call:
                if isinstance(resp, _wire.Chunk):
                    if assembler is not None and malformed is None:
                        try:
                            assembler.add(resp)
                        except ValueError as e:
                            malformed = str(e)
                    elif assembler is None and malformed is None:
                        malformed = "a mesh chunk came before the Result"
                    continue
                kind = resp.WhichOneof("payload")
                if kind == "accepted":
                    job_id = resp.accepted.job_id
                elif kind == "repair":
                    repair = resp.repair
                elif kind == "queue_update" and bar:
                    bar.note(f"queued: {resp.queue_update.queue_position} jobs ahead")
                elif kind == "progress":
                    m = resp.progress
                    p = Pass(job_id, getattr(m, "pass"),
                             m.vertices_left, m.removed, m.tried, dict(m.rejections), m.seconds,
                             m)
                    passes.append(p)
                    if bar:
                        bar.update(p)
                    if progress:
                        progress(p)
                elif kind == "result":
                    result = resp.result
                    repair = result.repair if result.HasField("repair") else repair
                    assembler = _wire.Assembler(result.output_vertices, result.output_faces,
                                                result.has_face_groups, result.face_field_names)
        except grpc.RpcError as e:
            code, details = e.code(), e.details() or ""
            # A stream reset before the status is a call cut by a proxy: a replica went away.
            if code == grpc.StatusCode.INTERNAL and details.startswith("Received RST_STREAM"):
                code = grpc.StatusCode.UNAVAILABLE
                details = (f"the call was cut before the server answered ({details}); a replica "
                           "behind a proxy went away?")
            raise _Failed(code, details, _pushback(e.trailing_metadata()), job_id) from None
        except BaseException:
            call.cancel()  # a raising progress callback or Ctrl-C ends the job on the server
            raise
        finally:
            with self._lock:
                self._calls.discard(call)
        if result is None or not result.job_id:
            raise _Failed(grpc.StatusCode.INTERNAL, "server ended the call without a result",
                          job_id=job_id)
        if malformed is None:
            try:
                mesh = assembler.finish()
            except ValueError as e:
                malformed = str(e)
        if malformed is not None:
            raise _Failed(grpc.StatusCode.DATA_LOSS, f"malformed result mesh: {malformed}",
                          job_id=job_id)
        return Outcome(mesh, result, result.job_id, passes, 1, repair)


def _pushback(trailers):
    """grpc-retry-pushback-ms of the trailers: ms, -1 when negative or unparseable, or None."""
    for key, value in trailers or ():
        if key == "grpc-retry-pushback-ms":
            try:
                ms = int(value)
            except ValueError:
                return -1
            return ms if ms >= 0 else -1
    return None


def _truncate(label):
    data = label.encode()[:_LABEL_BYTES]
    return data.decode(errors="ignore")
