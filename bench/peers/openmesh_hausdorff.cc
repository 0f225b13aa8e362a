#include "bench/peers/openmesh_hausdorff.h"

#include <vector>

#include "engine/io/openmesh.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModHausdorffT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#pragma GCC diagnostic pop

namespace femsimp::bench {

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

PeerRun RunOpenMeshHausdorff(const RawMesh& input, double tolerance) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> vh;
  vh.reserve(input.num_vertices());
  for (size_t v = 0; v < input.num_vertices(); ++v)
    vh.push_back(mesh.add_vertex(TriMesh::Point(input.positions[3 * v], input.positions[3 * v + 1],
                                                input.positions[3 * v + 2])));
  for (size_t f = 0; f < input.num_faces(); ++f)
    mesh.add_face(vh[input.triangles[3 * f]], vh[input.triangles[3 * f + 1]],
                  vh[input.triangles[3 * f + 2]]);
  mesh.request_face_normals();  // ModNormalFlipping needs them
  mesh.update_face_normals();
  PeerRun run;
  RunTimer timer(run);
  {
    OpenMesh::Decimater::DecimaterT<TriMesh> dec(mesh);
    OpenMesh::Decimater::ModQuadricT<TriMesh>::Handle quadric;
    OpenMesh::Decimater::ModHausdorffT<TriMesh>::Handle hausdorff;
    OpenMesh::Decimater::ModNormalFlippingT<TriMesh>::Handle flipping;
    dec.add(quadric);
    dec.add(hausdorff);
    dec.add(flipping);
    dec.module(hausdorff).set_tolerance(static_cast<float>(tolerance));
    dec.initialize();
    dec.decimate();             // 0 collapses asked: as many as the modules allow
    mesh.garbage_collection();  // before the decimater releases its status flags
  }
  timer.Stop();
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    run.output.positions.insert(run.output.positions.end(), {p[0], p[1], p[2]});
  }
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) run.output.triangles.push_back(static_cast<uint32_t>(v.idx()));
  return run;
}

}  // namespace femsimp::bench
