#include "tests/engine/small_meshes.h"

namespace femsimp::testing {

RawMesh FlatGrid(int n) {
  RawMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.positions.insert(m.positions.end(), {float(i), float(j), 0.f});
  auto id = [n](int i, int j) { return uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      // Alternate the diagonals so every vertex is surrounded symmetrically.
      if ((i + j) % 2 == 0) {
        m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j), id(i, j + 1)});
        m.triangles.insert(m.triangles.end(), {id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return m;
}

RawMesh Tetrahedron() {
  return {{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}, {}, {}};
}

RawMesh Octahedron() {
  return {{1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1},
          {4, 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 5, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3},
          {},
          {}};
}

RawMesh SingleTriangle() { return {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}, {}, {}}; }

}  // namespace femsimp::testing
