#include "bench/peers/openmesh_hausdorff.h"

#include "bench/peers/openmesh_soup.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModHausdorffT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#pragma GCC diagnostic pop

namespace femsimp::bench {

PeerRun RunOpenMeshHausdorff(const RawMesh& input, double tolerance) {
  TriMesh mesh;
  ToTriMesh(input, mesh);
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
  run.output = FromTriMesh(mesh);
  return run;
}

}  // namespace femsimp::bench
