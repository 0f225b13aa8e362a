#include "tests/support/meshes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "engine/io/mesh_io.h"
#include "engine/mesh.h"
#include "engine/mesh_checks.h"
#include "gtest/gtest.h"

namespace femsimp::testing {

Ring RegularFan(int n, float apex) {
  Ring r;
  r.center = 0;
  r.center_pos = {0, 0, apex};
  r.faces = n;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    r.nbr[i] = static_cast<uint32_t>(i + 1);
    r.pos[i] = {static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 0.0f};
    r.feature[i] = false;
    r.group[i] = 0;
    r.out[i] = static_cast<uint32_t>(3 * i);
  }
  return r;
}

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

RawMesh PreciseTetrahedron() {
  RawMesh m;
  m.positions = {0.1f,        -0.2f,          1.0f / 3.0f,   //
                 123.456789f, 1.23456789e-6f, 0.3f,          //
                 0.7f,        45.6f,          -2.0f / 7.0f,  //
                 3.14159265f, 2.5f,           -98.7654321f};
  // Oriented so that every face is counter-clockwise seen from outside.
  m.triangles = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
  return m;
}

RawMesh MakeTorus(int n, int m, double R, double r) {
  RawMesh mesh;
  mesh.positions.reserve(3 * size_t(n) * m);
  for (int i = 0; i < n; ++i) {
    double u = 2 * std::numbers::pi * i / n;
    for (int j = 0; j < m; ++j) {
      double v = 2 * std::numbers::pi * j / m;
      mesh.positions.push_back(float((R + r * std::cos(v)) * std::cos(u)));
      mesh.positions.push_back(float((R + r * std::cos(v)) * std::sin(u)));
      mesh.positions.push_back(float(r * std::sin(v)));
    }
  }
  mesh.triangles.reserve(6 * size_t(n) * m);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      uint32_t a = i * m + j, b = ((i + 1) % n) * m + j, c = ((i + 1) % n) * m + (j + 1) % m,
               d = i * m + (j + 1) % m;
      mesh.triangles.insert(mesh.triangles.end(), {a, b, c, a, c, d});
    }
  return mesh;
}

RawMesh ShellBesideSolidTorus() {
  const auto outward = [](double r, bool reversed) {
    RawMesh t = MakeTorus(96, 40, 3.0, r);
    if ((SignedVolume(t) < 0) != reversed)
      for (size_t f = 0; f < t.num_faces(); ++f)
        std::swap(t.triangles[3 * f + 1], t.triangles[3 * f + 2]);
    return t;
  };
  RawMesh out;
  const auto append = [&out](const RawMesh& part, float dx, uint32_t group) {
    const uint32_t base = static_cast<uint32_t>(out.num_vertices());
    for (size_t i = 0; i < part.positions.size(); ++i)
      out.positions.push_back(part.positions[i] + (i % 3 == 0 ? dx : 0.0f));
    for (uint32_t v : part.triangles) out.triangles.push_back(base + v);
    out.face_groups.insert(out.face_groups.end(), part.num_faces(), group);
  };
  append(outward(1.0, false), 0.0f, 1);
  append(outward(0.9, true), 0.0f, 1);  // the shell's inner side faces into the hollow
  append(outward(1.0, false), 10.0f, 2);
  return out;
}

void Append(RawMesh& m, const RawMesh& add, const std::array<float, 3>& shift) {
  const uint32_t base = static_cast<uint32_t>(m.num_vertices());
  for (size_t i = 0; i < add.positions.size(); ++i)
    m.positions.push_back(add.positions[i] + shift[i % 3]);
  for (uint32_t v : add.triangles) m.triangles.push_back(base + v);
}

RawMesh RandomSoup(uint32_t facets, uint32_t seed, float size) {
  RawMesh soup;
  uint32_t state = seed;
  const auto next = [&] {
    state = state * 1664525u + 1013904223u;  // a linear congruential generator: any platform
    return float(state >> 8) / float(1 << 24);
  };
  for (uint32_t f = 0; f < facets; ++f) {
    float centre[3] = {0, 0, 0};
    if (size < 1.0f)
      for (float& c : centre) c = next();
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) soup.positions.push_back(centre[k] + size * next());
      soup.triangles.push_back(3 * f + c);
    }
  }
  return soup;
}

RawMesh TurnedSkew(RawMesh m) {
  const DVec3 axis = (1.0 / std::sqrt(1.0 + 0.49 + 0.09)) * DVec3{1.0, 0.7, 0.3};
  const double c = std::cos(0.61), s = std::sin(0.61);
  for (size_t v = 0; v < m.num_vertices(); ++v) {  // Rodrigues' rotation
    const DVec3 p{m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
    const DVec3 r = c * p + s * Cross(axis, p) + ((1 - c) * Dot(axis, p)) * axis;
    m.positions[3 * v] = float(r.x);
    m.positions[3 * v + 1] = float(r.y);
    m.positions[3 * v + 2] = float(r.z);
  }
  return m;
}

RawMesh MakeBox(const std::array<double, 3>& size, const std::array<int, 3>& cells) {
  RawMesh mesh;
  std::map<std::array<int, 3>, uint32_t> ids;  // grid point -> vertex, shared by the sides
  auto vertex = [&](const std::array<int, 3>& g) {
    auto [it, added] = ids.emplace(g, static_cast<uint32_t>(ids.size()));
    if (added)
      for (int k = 0; k < 3; ++k) mesh.positions.push_back(float(size[k] * g[k] / cells[k]));
    return it->second;
  };
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;  // u x v points along +a
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < cells[u]; ++i)
        for (int j = 0; j < cells[v]; ++j) {
          std::array<uint32_t, 4> q;
          const int corner[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
          for (int c = 0; c < 4; ++c) {
            std::array<int, 3> g;
            g[a] = side * cells[a];
            g[u] = corner[c][0];
            g[v] = corner[c][1];
            q[c] = vertex(g);
          }
          if (side == 0) std::swap(q[1], q[3]);  // the -a side faces the other way
          mesh.triangles.insert(mesh.triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
        }
  }
  return mesh;
}

RawMesh BrokenTorus(int n, int m) {
  RawMesh mesh = MakeTorus(n, m);
  const uint32_t copies = uint32_t(mesh.num_vertices());
  mesh.positions.insert(mesh.positions.end(), mesh.positions.begin(),
                        mesh.positions.begin() + 3 * m);
  for (size_t c = 6 * size_t(n - 1) * m; c < mesh.triangles.size(); ++c)
    if (mesh.triangles[c] < uint32_t(m)) mesh.triangles[c] += copies;
  for (size_t f : {3, 10}) std::swap(mesh.triangles[3 * f + 1], mesh.triangles[3 * f + 2]);
  const uint32_t a = mesh.triangles[0], b = mesh.triangles[1], c = mesh.triangles[2];
  mesh.triangles.insert(mesh.triangles.end(), {a, b, c, a, b, a});
  return mesh;
}

BrokenTorusRepairs BrokenTorusRepairsOf(int m) {
  BrokenTorusRepairs r;
  r.welded = r.stitched = size_t(m);
  return r;
}

RawMesh CubeWithAFoldOnTop() {
  RawMesh m;
  for (uint32_t i = 0; i < 8; ++i)
    m.positions.insert(m.positions.end(), {float(i & 1), float(i >> 1 & 1), float(i >> 2 & 1)});
  m.positions.insert(m.positions.end(), {0.7f, 0.3f, 1.0f});
  // Quads counter-clockwise seen from outside: -x, +x, -y, +y, -z.
  const uint32_t quads[5][4] = {
      {0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}};
  for (const auto& q : quads)
    m.triangles.insert(m.triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  m.triangles.insert(m.triangles.end(), {4, 5, 7, 7, 8, 4, 7, 6, 8, 6, 4, 8});
  return m;
}

RawMesh WithGroupsAndFields(RawMesh mesh) {
  const size_t nf = mesh.num_faces();
  mesh.face_groups.resize(nf);
  mesh.face_fields = {{"pressure", {}}, {"heat_flux", {}}};
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t g = 10 + uint32_t(4 * f / nf);
    mesh.face_groups[f] = g;
    mesh.face_fields[0].values.push_back(1000.0f + float(g));
    mesh.face_fields[1].values.push_back(-0.5f * float(g));
  }
  return mesh;
}

size_t ExpectGroupsAndFields(const RawMesh& out) {
  EXPECT_EQ(out.face_groups.size(), out.num_faces());
  EXPECT_EQ(out.face_fields.size(), 2u);
  if (out.face_groups.size() != out.num_faces() || out.face_fields.size() != 2) return 0;
  EXPECT_EQ(out.face_fields[0].name, "pressure");
  EXPECT_EQ(out.face_fields[1].name, "heat_flux");
  std::set<uint32_t> seen;
  for (size_t f = 0; f < out.num_faces(); ++f) {
    const uint32_t g = out.face_groups[f];
    EXPECT_TRUE(g >= 10 && g <= 13) << "face " << f << " group " << g;
    if (!(g >= 10 && g <= 13)) return 0;
    seen.insert(g);
    EXPECT_EQ(out.face_fields[0].values[f], 1000.0f + float(g)) << "face " << f;
    EXPECT_EQ(out.face_fields[1].values[f], -0.5f * float(g)) << "face " << f;
  }
  return seen.size();
}

std::string TestDataPath(const std::string& name) {
  return std::string(FEMSIMP_TEST_DATA) + "/" + name;
}

RawMesh LoadTestMesh(const std::string& name) {
  absl::StatusOr<RawMesh> raw = ReadMeshFile(TestDataPath(name));
  EXPECT_TRUE(raw.ok()) << raw.status();
  return raw.ok() ? *std::move(raw) : RawMesh{};
}

SimplifyRun SimplifyChecked(const RawMesh& input, const SimplifyOptions& options) {
  return SimplifyCheckedWith(input, options, SimplifyControl{});
}

SimplifyRun SimplifyCheckedWith(const RawMesh& input, const SimplifyOptions& options,
                                const SimplifyControl& control) {
  SimplifyRun run;
  run.input = input;
  absl::StatusOr<Mesh> mesh = Mesh::Build(input);
  EXPECT_TRUE(mesh.ok()) << mesh.status();
  if (!mesh.ok()) return run;
  absl::StatusOr<SimplifyResult> result = Simplify(*mesh, options, control);
  EXPECT_TRUE(result.ok()) << result.status();
  if (!result.ok()) return run;
  EXPECT_EQ(HalfEdgeInvariantViolation(*mesh), "");
  run.result = *result;
  run.output = mesh->ToRaw();
  return run;
}

double SignedVolume(const RawMesh& m) {
  double v = 0;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const float* p[3];
    for (int i = 0; i < 3; ++i) p[i] = &m.positions[3 * m.triangles[3 * f + i]];
    v += (p[0][0] * (double(p[1][1]) * p[2][2] - double(p[1][2]) * p[2][1]) -
          p[0][1] * (double(p[1][0]) * p[2][2] - double(p[1][2]) * p[2][0]) +
          p[0][2] * (double(p[1][0]) * p[2][1] - double(p[1][1]) * p[2][0])) /
         6;
  }
  return v;
}

double MinAngleDegrees(const RawMesh& mesh, size_t face) {
  double p[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) p[i][k] = mesh.positions[3 * mesh.triangles[3 * face + i] + k];
  double smallest = 180.0;
  for (int i = 0; i < 3; ++i) {
    double u[3], w[3];
    for (int k = 0; k < 3; ++k) {
      u[k] = p[(i + 1) % 3][k] - p[i][k];
      w[k] = p[(i + 2) % 3][k] - p[i][k];
    }
    const double d = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
    const double nu = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    const double nw = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    smallest = std::min(smallest,
                        std::acos(std::clamp(d / (nu * nw), -1.0, 1.0)) * 180.0 / std::numbers::pi);
  }
  return smallest;
}

std::function<bool()> CancelOnceRemoving(const Mesh& mesh) {
  return [&mesh] {
    for (uint32_t v = 0; v < mesh.vertex_capacity(); ++v)
      if (mesh.IsRemoved(v)) return true;
    return false;
  };
}

double PointTriangleDistance(const DVec3& p, const DVec3& a, const DVec3& b, const DVec3& c) {
  const DVec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = Dot(ab, ap), d2 = Dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return Norm(p - a);
  const DVec3 bp = p - b;
  const double d3 = Dot(ab, bp), d4 = Dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return Norm(p - b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return Norm(p - (a + (d1 / (d1 - d3)) * ab));
  const DVec3 cp = p - c;
  const double d5 = Dot(ab, cp), d6 = Dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return Norm(p - c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return Norm(p - (a + (d2 / (d2 - d6)) * ac));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return Norm(p - (b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)));
  const double denom = 1.0 / (va + vb + vc);
  return Norm(p - (a + (vb * denom) * ab + (vc * denom) * ac));
}

}  // namespace femsimp::testing
