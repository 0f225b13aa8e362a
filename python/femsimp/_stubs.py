"""The gRPC stubs of proto/femsimp/v1/femsimp.proto, as modules femsimp.v1.femsimp_pb2(_grpc).

Installed (CMake install), the stubs generated at build time lie in the package's v1/ folder.
From a checkout, the proto next to the package is compiled on first use with Debian's protoc
and grpc_python_plugin into a cache folder named by the proto's hash, so an edited proto is
compiled again and a stale stub is never used. The cache folder joins the package's __path__,
which is what lets the generated code's own `from femsimp.v1 import femsimp_pb2` resolve.
"""
import hashlib
import importlib
import os
import shutil
import subprocess
import sys
import tempfile

_PKG_DIR = os.path.dirname(os.path.abspath(__file__))
PROTO_REL = os.path.join("femsimp", "v1", "femsimp.proto")
# python/femsimp/ -> repository root -> proto/
CHECKOUT_PROTO_ROOT = os.path.normpath(os.path.join(_PKG_DIR, "..", "..", "proto"))
GRPC_PLUGIN = os.environ.get("FEMSIMP_GRPC_PYTHON_PLUGIN", "/usr/bin/grpc_python_plugin")
PROTOC = os.environ.get("FEMSIMP_PROTOC", "protoc")


class StubError(RuntimeError):
    """The stubs could not be found or generated; the message says what to install."""


def _cache_root():
    base = os.environ.get("FEMSIMP_CACHE_DIR")
    if not base:
        xdg = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        base = os.path.join(xdg, "femsimp")
    return os.path.join(base, "stubs")


def generate(proto_root, out_dir):
    """Runs protoc on proto_root/femsimp/v1/femsimp.proto, writing femsimp/v1/*.py under out_dir."""
    if shutil.which(PROTOC) is None or not os.path.exists(GRPC_PLUGIN):
        raise StubError(
            f"cannot generate the gRPC stubs: {PROTOC} or {GRPC_PLUGIN} is missing "
            "(Debian: apt-get install protobuf-compiler protobuf-compiler-grpc)")
    os.makedirs(out_dir, exist_ok=True)
    cmd = [PROTOC, f"-I{proto_root}", f"--python_out={out_dir}", f"--grpc_python_out={out_dir}",
           f"--plugin=protoc-gen-grpc_python={GRPC_PLUGIN}", os.path.join(proto_root, PROTO_REL)]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise StubError(f"protoc failed on {os.path.join(proto_root, PROTO_REL)}: "
                        f"{done.stderr.strip()}")


def _checkout_stub_dir():
    """The cache folder holding stubs of the checkout's proto, generated when missing."""
    proto = os.path.join(CHECKOUT_PROTO_ROOT, PROTO_REL)
    with open(proto, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()[:20]
    root = _cache_root()
    target = os.path.join(root, digest)
    if os.path.exists(os.path.join(target, "femsimp", "v1", "femsimp_pb2_grpc.py")):
        return target
    try:
        os.makedirs(root, exist_ok=True)
    except OSError:
        root = os.path.join(tempfile.gettempdir(), f"femsimp-stubs-{os.getuid()}")
        os.makedirs(root, exist_ok=True)
        target = os.path.join(root, digest)
        if os.path.exists(os.path.join(target, "femsimp", "v1", "femsimp_pb2_grpc.py")):
            return target
    # Generated aside and renamed into place: concurrent first uses never see half a folder.
    tmp = tempfile.mkdtemp(prefix=f".{digest}-", dir=root)
    try:
        generate(CHECKOUT_PROTO_ROOT, tmp)
        try:
            os.rename(tmp, target)
        except OSError:
            if not os.path.isdir(target):  # not another process's win: a real failure
                raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return target


def load():
    """Returns (femsimp_pb2, femsimp_pb2_grpc)."""
    pkg = sys.modules["femsimp"]
    installed = os.path.exists(os.path.join(_PKG_DIR, "v1", "femsimp_pb2.py"))
    from_checkout = os.path.exists(os.path.join(CHECKOUT_PROTO_ROOT, PROTO_REL))
    if from_checkout and not installed:
        stub_pkg = os.path.join(_checkout_stub_dir(), "femsimp")
        if stub_pkg not in pkg.__path__:
            pkg.__path__.append(stub_pkg)
    elif not installed:
        raise StubError(f"no gRPC stubs in {_PKG_DIR}/v1 and no proto at "
                        f"{os.path.join(CHECKOUT_PROTO_ROOT, PROTO_REL)}: reinstall femsimp")
    pb2 = importlib.import_module("femsimp.v1.femsimp_pb2")
    pb2_grpc = importlib.import_module("femsimp.v1.femsimp_pb2_grpc")
    return pb2, pb2_grpc
