#include "bench/speed_peers.h"

#include <cfloat>
#include <chrono>
#include <vector>

#include <meshoptimizer.h>

#include "bench/heap_counter.h"
#include "bench/peers/openmesh_soup.h"
#include "bench/peers/peer_run.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#pragma GCC diagnostic pop

namespace femsimp::bench {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

SpeedSample RunOpenMeshDecimater(const RawMesh& in, uint64_t target_vertices, RawMesh* output) {
  const int64_t live0 = LiveHeapBytes();
  ResetHeapPeak();
  SpeedSample s;
  TriMesh mesh;
  auto t0 = Clock::now();
  ToTriMesh(in, mesh);
  const int64_t live1 = LiveHeapBytes();
  s.build_seconds = Seconds(t0, Clock::now());
  t0 = Clock::now();
  const double cpu0 = ProcessCpuSeconds();
  {
    OpenMesh::Decimater::DecimaterT<TriMesh> dec(mesh);
    OpenMesh::Decimater::ModQuadricT<TriMesh>::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<TriMesh>::Handle flipping;
    OpenMesh::Decimater::ModAspectRatioT<TriMesh>::Handle aspect;
    dec.add(quadric);
    dec.add(flipping);
    dec.add(aspect);
    dec.initialize();
    dec.decimate_to(target_vertices);
    mesh.garbage_collection();  // before the decimater releases its status flags
  }
  s.seconds = Seconds(t0, Clock::now());
  s.cpu_seconds = ProcessCpuSeconds() - cpu0;
  s.total_bytes = PeakHeapBytes() - live0;
  s.work_bytes = PeakHeapBytes() - live1;
  if (output) *output = FromTriMesh(mesh);
  return s;
}

SpeedSample RunMeshoptSimplify(const RawMesh& in, uint64_t target_faces, RawMesh* output) {
  const int64_t live0 = LiveHeapBytes();
  ResetHeapPeak();
  SpeedSample s;
  std::vector<uint32_t> dst(in.triangles.size());
  float error = 0;
  const auto t0 = Clock::now();
  const double cpu0 = ProcessCpuSeconds();
  // FLT_MAX: no error bound, stop at the count.
  const size_t n = meshopt_simplify(dst.data(), in.triangles.data(), in.triangles.size(),
                                    in.positions.data(), in.num_vertices(), 3 * sizeof(float),
                                    3 * target_faces, FLT_MAX, meshopt_SimplifyLockBorder, &error);
  s.seconds = Seconds(t0, Clock::now());
  s.cpu_seconds = ProcessCpuSeconds() - cpu0;
  s.total_bytes = s.work_bytes = PeakHeapBytes() - live0;
  if (output) *output = CompactSoup(in.positions, dst.data(), n / 3);
  return s;
}

}  // namespace femsimp::bench
