#!/usr/bin/python3
"""Many small boxes, each missing its top face: an assembly whose exporter dropped a flat face
of every part, for the cost of `--fill-holes planar` (one opening per box).

Usage: bench/make_open_boxes.py PER_SIDE OUT.off

PER_SIDE^2 boxes of unit base on a grid with gaps of half a unit, each a thousandth taller than
the one before (so that no two openings lie in one plane: one fill each); each keeps 10 of its
12 facets.
"""
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    per_side, out = int(sys.argv[1]), sys.argv[2]
    if per_side < 1:
        sys.exit("PER_SIDE must be at least 1")
    corners = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
    # Counter-clockwise seen from outside; the top (z = 1) left out.
    faces = [(0, 2, 3), (0, 3, 1), (0, 1, 5), (0, 5, 4), (1, 3, 7), (1, 7, 5),
             (3, 2, 6), (3, 6, 7), (2, 0, 4), (2, 4, 6)]
    positions, facets = [], []
    for i in range(per_side):
        for j in range(per_side):
            base = len(positions)
            height = 1 + 1e-3 * (i * per_side + j)
            positions += [(1.5 * i + x, 1.5 * j + y, z * height) for x, y, z in corners]
            facets += [(base + a, base + b, base + c) for a, b, c in faces]
    with open(out, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(positions), len(facets)))
        f.writelines("%.9g %.9g %.9g\n" % p for p in positions)
        f.writelines("3 %d %d %d\n" % t for t in facets)


if __name__ == "__main__":
    main()
