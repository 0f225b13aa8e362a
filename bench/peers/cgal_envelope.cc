#include "bench/peers/cgal_envelope.h"

#include <cstddef>
#include <vector>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_filter.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Polyhedral_envelope_filter.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

namespace femsimp::bench {
namespace {

namespace SMS = CGAL::Surface_mesh_simplification;
using Kernel = CGAL::Simple_cartesian<double>;
using Surface = CGAL::Surface_mesh<Kernel::Point_3>;

// Count_stop_predicate(0) never stops (the edge count cannot fall below 0), so the run ends
// when no edge passes the filters; the limit (CPU seconds, like the reported times) is checked
// before each collapse, which is where the time goes (the envelope tests of the new faces).
class LimitStop {
 public:
  LimitStop(double cpu_deadline, bool* timed_out)
      : cpu_deadline_(cpu_deadline), timed_out_(timed_out) {}
  template <typename F, typename Profile>
  bool operator()(const F& cost, const Profile& profile, std::size_t initial,
                  std::size_t current) const {
    if (count_(cost, profile, initial, current)) return true;
    if (cpu_deadline_ > 0 && ProcessCpuSeconds() > cpu_deadline_) *timed_out_ = true;
    return *timed_out_;
  }

 private:
  SMS::Count_stop_predicate<Surface> count_{0};
  double cpu_deadline_;  // 0: none
  bool* timed_out_;
};

}  // namespace

PeerRun RunCgalEnvelope(const RawMesh& input, double tolerance, double time_limit) {
  PeerRun run;
  Surface mesh;
  std::vector<Surface::Vertex_index> vi;
  vi.reserve(input.num_vertices());
  for (size_t v = 0; v < input.num_vertices(); ++v)
    vi.push_back(mesh.add_vertex(Kernel::Point_3(input.positions[3 * v], input.positions[3 * v + 1],
                                                 input.positions[3 * v + 2])));
  for (size_t f = 0; f < input.num_faces(); ++f)
    if (mesh.add_face(vi[input.triangles[3 * f]], vi[input.triangles[3 * f + 1]],
                      vi[input.triangles[3 * f + 2]]) == Surface::null_face()) {
      run.error = "CGAL's Surface_mesh refuses a face (non-manifold input)";
      return run;
    }

  using Filter = SMS::Polyhedral_envelope_filter<Kernel, SMS::Bounded_normal_change_filter<>>;
  RunTimer timer(run);
  LimitStop stop(time_limit > 0 ? ProcessCpuSeconds() + time_limit : 0.0, &run.timed_out);
  Filter filter(tolerance);  // builds the envelope at its first use, inside the timed part
  SMS::edge_collapse(mesh, stop,
                     CGAL::parameters::get_cost(SMS::LindstromTurk_cost<Surface>())
                         .get_placement(SMS::LindstromTurk_placement<Surface>())
                         .filter(filter));
  timer.Stop();

  mesh.collect_garbage();  // vertices and faces numbered 0..n-1 again
  for (Surface::Vertex_index v : mesh.vertices()) {
    const Kernel::Point_3& p = mesh.point(v);
    run.output.positions.insert(
        run.output.positions.end(),
        {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
  }
  for (Surface::Face_index f : mesh.faces())
    for (Surface::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      run.output.triangles.push_back(static_cast<uint32_t>(v.idx()));
  return run;
}

}  // namespace femsimp::bench
