"""Fixtures of the Python client's tests: a femsimp-server from the build tree on a free
loopback port (FEMSIMP_SERVER_BIN, set by tests/python/CMakeLists.txt), and meshes made here."""
import os
import re
import signal
import subprocess
import sys
import threading

import numpy as np
import pytest

REPO = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(REPO, "python"))


def required_env(name):
    value = os.environ.get(name)
    if not value:
        pytest.fail(f"{name} is not set: run these tests through ctest (tests/python), or set it")
    return value


class Server:
    """femsimp-server on 127.0.0.1:0; its stderr drained by a thread (a full pipe would stall it)."""

    def __init__(self, *flags):
        binary = required_env("FEMSIMP_SERVER_BIN")
        self.proc = subprocess.Popen([binary, "--listen=127.0.0.1:0", "--metrics_listen=", *flags],
                                     stderr=subprocess.PIPE, text=True)
        self.log = []
        port = None
        for line in self.proc.stderr:
            self.log.append(line)
            m = re.search(r"listening on \S+ \(port (\d+)\)", line)
            if m:
                port = int(m.group(1))
                break
        if port is None:
            self.proc.kill()
            raise RuntimeError("femsimp-server did not report its port:\n" + "".join(self.log))
        self.address = f"127.0.0.1:{port}"
        self.drain = threading.Thread(target=lambda: self.log.extend(self.proc.stderr),
                                      daemon=True)
        self.drain.start()

    def stop(self):
        self.proc.send_signal(signal.SIGTERM)
        try:
            self.proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.drain.join(timeout=10)
        self.proc.stderr.close()


@pytest.fixture(scope="session")
def server():
    s = Server("--workers=2", "--threads_per_job=1")
    yield s
    s.stop()


@pytest.fixture
def client(server):
    import femsimp
    with femsimp.Client(server.address, progress_bar=False) as c:
        yield c


def _box_sides(n, split):
    """The closed surface of the unit cube, n x n quads per side, outward, welded: points, the
    cells split(quads) makes of each side's quads (a, b, c, d), and the side (0..5) of each."""
    u, v = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1), indexing="ij")
    u, v = u.ravel(), v.ravel()
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a = (i * (n + 1) + j).ravel()
    cell = split(np.stack([a, a + n + 1, a + n + 2, a + 1], axis=1))
    pts, cells, sides = [], [], []
    for side in range(6):
        axis, high = divmod(side, 2)
        p = np.zeros(((n + 1) ** 2, 3))
        others = [k for k in range(3) if k != axis]
        p[:, axis] = high
        p[:, others[0]], p[:, others[1]] = u, v
        c = cell.copy()
        normal = np.cross(p[c[0, 1]] - p[c[0, 0]], p[c[0, 2]] - p[c[0, 0]])
        if (normal[axis] > 0) != bool(high):
            c = c[:, ::-1]
        cells.append(c + sum(len(x) for x in pts))
        pts.append(p)
        sides.append(np.full(len(c), side))
    points = np.concatenate(pts)
    # Weld the sides' shared edges.
    unique, inverse = np.unique(np.round(points, 9), axis=0, return_inverse=True)
    return unique, inverse.ravel()[np.concatenate(cells)], np.concatenate(sides)


def box_surface(n):
    """The closed surface of the unit cube, n x n quads per side split into triangles, outward.
    Returns points (float64), triangles (int64), side (0..5) of each triangle."""
    return _box_sides(n, lambda q: np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]]))


def quad_box(n):
    """The same cube as n x n quads per side: points, quads, side of each quad."""
    return _box_sides(n, lambda q: q)


def sphere_surface(n):
    """A closed UV sphere of radius 1 (about 2 n^2 triangles), outward."""
    theta = np.linspace(0, np.pi, n + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3)
    points = np.concatenate([[[0, 0, 1]], ring, [[0, 0, -1]]])
    m = 2 * n
    rows = n - 1
    idx = 1 + np.arange(rows * m).reshape(rows, m)
    nxt = np.roll(idx, -1, axis=1)
    tris = [np.stack([np.zeros(m, int), idx[0], nxt[0]], 1)]
    for r in range(rows - 1):
        tris.append(np.stack([idx[r], idx[r + 1], nxt[r + 1]], 1))
        tris.append(np.stack([idx[r], nxt[r + 1], nxt[r]], 1))
    tris.append(np.stack([np.full(m, len(points) - 1), nxt[-1], idx[-1]], 1))
    return points, np.concatenate(tris)
