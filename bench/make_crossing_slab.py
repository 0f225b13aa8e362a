#!/usr/bin/python3
"""A large closed slab with vertices written wrongly, for the crossing repair's cost.

Usage: bench/make_crossing_slab.py CELLS WRONG OUT.off [SEED]

The slab is CELLS x CELLS unit cells on top and bottom, one cell high (4 CELLS^2 + 8 CELLS
facets). WRONG vertices of its top, at least four cells apart, are moved through the bottom to
half a cell below it (a digit lost in a coordinate), so that their facets cross the bottom's.
"""
import random
import sys


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    cells, wrong, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    seed = int(sys.argv[4]) if len(sys.argv) == 5 else 7
    if cells < 10 or wrong < 0 or wrong > ((cells - 6) // 4) ** 2:
        sys.exit("CELLS must be at least 10 and WRONG at most ((CELLS - 6) / 4)^2")
    index, positions, facets = {}, [], []

    def vertex(x, y, z):
        if (x, y, z) not in index:
            index[(x, y, z)] = len(positions)
            positions.append([x, y, z])
        return index[(x, y, z)]

    def quad(a, b, c, d):  # counter-clockwise seen from outside
        facets.extend([(a, b, c), (a, c, d)])

    n = cells
    for i in range(n):
        for j in range(n):
            quad(vertex(i, j, 1), vertex(i + 1, j, 1), vertex(i + 1, j + 1, 1), vertex(i, j + 1, 1))
            quad(vertex(i, j, 0), vertex(i, j + 1, 0), vertex(i + 1, j + 1, 0), vertex(i + 1, j, 0))
    for i in range(n):
        quad(vertex(i, 0, 0), vertex(i + 1, 0, 0), vertex(i + 1, 0, 1), vertex(i, 0, 1))
        quad(vertex(i + 1, n, 0), vertex(i, n, 0), vertex(i, n, 1), vertex(i + 1, n, 1))
        quad(vertex(0, i + 1, 0), vertex(0, i, 0), vertex(0, i, 1), vertex(0, i + 1, 1))
        quad(vertex(n, i, 0), vertex(n, i + 1, 0), vertex(n, i + 1, 1), vertex(n, i, 1))
    rng = random.Random(seed)
    slots = [(i, j) for i in range(3, n - 3, 4) for j in range(3, n - 3, 4)]
    for i, j in rng.sample(slots, wrong):
        positions[index[(i, j, 1)]] = [i + 0.1, j + 0.2, -0.5]
    with open(out, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(positions), len(facets)))
        f.writelines("%.6g %.6g %.6g\n" % tuple(p) for p in positions)
        f.writelines("3 %d %d %d\n" % t for t in facets)


if __name__ == "__main__":
    main()
