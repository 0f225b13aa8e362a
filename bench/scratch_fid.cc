#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <chrono>
#include "engine/io/mesh_io.h"
#include "engine/simplify.h"
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;
SM ToSM(const femsimp::RawMesh& r) {
  std::vector<K::Point_3> pts; std::vector<std::vector<size_t>> polys;
  for (size_t i = 0; i < r.num_vertices(); ++i) pts.emplace_back(r.positions[3*i], r.positions[3*i+1], r.positions[3*i+2]);
  for (size_t f = 0; f < r.num_faces(); ++f) polys.push_back({r.triangles[3*f], r.triangles[3*f+1], r.triangles[3*f+2]});
  SM m; PMP::polygon_soup_to_polygon_mesh(pts, polys, m); return m;
}
int main(int argc, char** argv) {
  auto raw = femsimp::ReadMeshFile(argv[1]);
  if (!raw.ok()) { printf("%s\n", raw.status().ToString().c_str()); return 1; }
  if (!strcmp(argv[2], "hd")) {
    auto other = femsimp::ReadMeshFile(argv[3]);
    SM a = ToSM(*raw), b = ToSM(*other);
    double tol = atof(argv[4]);
    double h1 = PMP::approximate_Hausdorff_distance<CGAL::Sequential_tag>(a, b, PMP::parameters::number_of_points_per_area_unit(4000/ (tol*tol*1e4) ));
    double h2 = PMP::approximate_Hausdorff_distance<CGAL::Sequential_tag>(b, a, PMP::parameters::number_of_points_per_area_unit(4000/ (tol*tol*1e4)));
    printf("H %g %g  (tol %g)\n", h1, h2, tol);
    return 0;
  }
  femsimp::SimplifyOptions o;
  o.tolerance_relative = atof(argv[2]);
  o.threads = argc > 3 ? atoi(argv[3]) : 1;
  if (argc > 4 && !strcmp(argv[4], "q")) o.cost = femsimp::CostKind::kQuadric;
  if (argc > 5) { o.min_angle_deg = atof(argv[5]); }
  if (argc > 6) { o.max_normal_deviation_deg = atof(argv[6]); }
  if (getenv("FA")) o.feature_angle_deg = atof(getenv("FA"));
  auto mesh = femsimp::Mesh::Build(*raw);
  auto t0 = std::chrono::steady_clock::now();
  auto res = femsimp::Simplify(*mesh, o);
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!res.ok()) { printf("%s\n", res.status().ToString().c_str()); return 1; }
  auto out = mesh->ToRaw();
  SM a = ToSM(*raw), b = ToSM(out);
  double tol = res->tolerance_abs;
  double h1 = PMP::approximate_Hausdorff_distance<CGAL::Sequential_tag>(a, b, PMP::parameters::number_of_points_per_area_unit(4000/ (tol*tol*1e4) ));
  double h2 = PMP::approximate_Hausdorff_distance<CGAL::Sequential_tag>(b, a, PMP::parameters::number_of_points_per_area_unit(4000/ (tol*tol*1e4)));
  printf("%s tol=%g v %lu->%lu bound=%g H(a,b)=%g H(b,a)=%g  fe=%lu corners=%lu t=%.3fs rej:", argv[1], tol, res->input_vertices, res->output_vertices, res->deviation_bound, h1, h2, res->feature_edges, res->corner_vertices, secs);
  std::array<uint64_t, (int)femsimp::Reject::kCount> rj{};
  for (auto& p : res->passes) for (int i = 0; i < (int)femsimp::Reject::kCount; ++i) rj[i] += p.rejections[i];
  for (int i = 0; i < (int)femsimp::Reject::kCount; ++i) printf(" %s=%lu", femsimp::RejectName((femsimp::Reject)i), rj[i]);
  printf("\n");
  if (argc > 7) femsimp::WriteMeshFile(argv[7], out);
}
