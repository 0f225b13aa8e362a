"""Exceptions and warnings of the femsimp client."""
import grpc

# What a code means for a femsimp user (client/remote_call.cc GrpcCodeHint).
_HINTS = {
    grpc.StatusCode.CANCELLED: "the job was cancelled (by you, CancelJob or the server)",
    grpc.StatusCode.INVALID_ARGUMENT: "the server rejected the request or the mesh",
    grpc.StatusCode.DEADLINE_EXCEEDED: "the job did not finish within the deadline",
    grpc.StatusCode.NOT_FOUND: "no such job or method on the server",
    grpc.StatusCode.RESOURCE_EXHAUSTED: "the server is full or the mesh exceeds one of its limits",
    grpc.StatusCode.UNIMPLEMENTED: "the server does not support this (back end or feature not "
                                   "available, or a version mismatch)",
    grpc.StatusCode.INTERNAL: "the server failed internally",
    grpc.StatusCode.UNAVAILABLE: "the server is not reachable or is shutting down; retry later",
    grpc.StatusCode.DATA_LOSS: "the result mesh arrived incomplete or malformed",
    grpc.StatusCode.UNAUTHENTICATED: "the server refused the client's credentials",
    grpc.StatusCode.PERMISSION_DENIED: "the server refused the client's credentials",
}


class FemsimpError(Exception):
    """A call failed: `code` is its grpc.StatusCode, `details` the server's message.

    `pushback_ms` is the server's grpc-retry-pushback-ms when it sent one (queue full),
    `attempts` how many calls the job took, `job_id` the job's id when it was accepted."""

    def __init__(self, code, details, address="", pushback_ms=None, attempts=1, job_id=""):
        self.code = code
        self.details = details
        self.address = address
        self.pushback_ms = pushback_ms
        self.attempts = attempts
        self.job_id = job_id
        where = f"{address}: " if address else ""
        super().__init__(f"{where}{_HINTS.get(code, 'the call failed')} ({code.name}: {details})")

    @property
    def exit_code(self):
        """The C++ CLI's exit code for this status: 20 + the gRPC code (client/exit_codes.h)."""
        return 20 + self.code.value[0]


class OptionError(ValueError):
    """An option is unknown, of the wrong type or out of range; raised before any upload."""


class MeshError(ValueError):
    """The input mesh cannot be sent: wrong shapes, an index out of range, a non-finite value,
    or (strict=True) cells or data femsimp does not simplify. The message says what and where."""


class FemsimpWarning(UserWarning):
    """Something of the input that femsimp does not simplify was left out of the result."""
