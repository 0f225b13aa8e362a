#!/usr/bin/python3
"""Writes tests/data/fandisk_groups_fields.ply: fandisk with a face group per dominant normal
direction (ids 1..6) and two face fields, `pressure` varying with height and `load` uniform per
group. A fixed, committed input for the golden-output test; rerun only to change the fixture."""
import sys

import numpy as np


def read_off(path):
    with open(path) as f:
        words = f.read().split()
    assert words[0] == "OFF"
    nv, nf = int(words[1]), int(words[2])
    pos = np.array(words[4 : 4 + 3 * nv], dtype=np.float64).reshape(nv, 3)
    faces = np.array(words[4 + 3 * nv : 4 + 3 * nv + 4 * nf], dtype=np.int64).reshape(nf, 4)[:, 1:]
    return pos, faces


def main(src, dst):
    pos, faces = read_off(src)
    a, b, c = pos[faces[:, 0]], pos[faces[:, 1]], pos[faces[:, 2]]
    normal = np.cross(b - a, c - a)
    axis = np.argmax(np.abs(normal), axis=1)
    sign = normal[np.arange(len(faces)), axis] < 0
    group = 1 + 2 * axis + sign
    z = (a[:, 2] + b[:, 2] + c[:, 2]) / 3.0
    pressure = 1.0 + 0.1 * (z - z.min()) / (z.max() - z.min())
    load = 10.0 * group
    with open(dst, "w") as f:
        f.write("ply\nformat ascii 1.0\n")
        f.write(f"element vertex {len(pos)}\nproperty float x\nproperty float y\nproperty float z\n")
        f.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\n")
        f.write("property int group\nproperty float pressure\nproperty float load\nend_header\n")
        for p in pos:
            f.write(f"{p[0]:.9g} {p[1]:.9g} {p[2]:.9g}\n")
        for t, g, pr, ld in zip(faces, group, pressure, load):
            f.write(f"3 {t[0]} {t[1]} {t[2]} {g} {pr:.7g} {ld:.7g}\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
