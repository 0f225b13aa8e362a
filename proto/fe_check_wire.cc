#include "proto/fe_check_wire.h"

#include <algorithm>

namespace femsimp::wire {
namespace {

fecheck::FeCheckOptions OptionsOf(const v1::FeCheckOptions& in) {
  fecheck::FeCheckOptions o;
  if (in.youngs_modulus() != 0) o.material.youngs_modulus = in.youngs_modulus();
  if (in.has_poisson_ratio()) o.material.poisson_ratio = in.poisson_ratio();
  if (in.density() != 0) o.material.density = in.density();
  if (in.unit_scale() != 0) o.unit_scale = in.unit_scale();
  if (in.modes() != 0) o.modes = in.modes();
  if (in.has_mesh_size()) o.mesh_size = in.mesh_size();
  o.keep_surface = !in.refine_surface();
  return o;
}

void SolidToProto(const fecheck::SolidFigures& f, v1::FeSolid* out) {
  out->set_surface_faces(static_cast<uint64_t>(f.surface_faces));
  out->set_tetrahedra(static_cast<uint64_t>(f.tetrahedra));
  out->set_nodes(static_cast<uint64_t>(f.nodes));
  out->set_solver_nodes(static_cast<uint64_t>(f.solver_nodes));
  out->set_components(static_cast<uint32_t>(f.components));
  out->set_volume(f.volume);
  out->set_mass(f.mass);
  for (double c : f.centroid) out->add_centroid(c);
  for (double m : f.principal_moments) out->add_principal_moments(m);
  out->set_diagonal(f.diagonal);
  for (double hz : f.frequencies_hz) out->add_frequencies_hz(hz);
  out->set_rigid_modes(static_cast<uint32_t>(f.rigid_modes));
  out->set_bodies_meshed_apart(static_cast<uint32_t>(f.bodies_meshed_apart));
}

fecheck::SolidFigures SolidFromProto(const v1::FeSolid& in) {
  fecheck::SolidFigures f;
  f.surface_faces = static_cast<int64_t>(in.surface_faces());
  f.tetrahedra = static_cast<int64_t>(in.tetrahedra());
  f.nodes = static_cast<int64_t>(in.nodes());
  f.solver_nodes = static_cast<int64_t>(in.solver_nodes());
  f.components = static_cast<int>(in.components());
  f.volume = in.volume();
  f.mass = in.mass();
  for (int k = 0; k < std::min(3, in.centroid_size()); ++k) f.centroid[k] = in.centroid(k);
  for (int k = 0; k < std::min(3, in.principal_moments_size()); ++k)
    f.principal_moments[k] = in.principal_moments(k);
  f.diagonal = in.diagonal();
  f.frequencies_hz.assign(in.frequencies_hz().begin(), in.frequencies_hz().end());
  f.rigid_modes = static_cast<int>(in.rigid_modes());
  f.bodies_meshed_apart = static_cast<int>(in.bodies_meshed_apart());
  return f;
}

}  // namespace

absl::StatusOr<fecheck::FeCheckOptions> FeCheckOptionsFromProto(const v1::FeCheckOptions& in) {
  fecheck::FeCheckOptions o = OptionsOf(in);
  if (absl::Status s = fecheck::ValidateFeCheckOptions(o); !s.ok()) return s;
  return o;
}

void ToProto(const fecheck::FeCheckOptions& o, v1::FeCheckOptions* out) {
  out->set_youngs_modulus(o.material.youngs_modulus);
  out->set_poisson_ratio(o.material.poisson_ratio);
  out->set_density(o.material.density);
  out->set_unit_scale(o.unit_scale);
  out->set_modes(o.modes);
  out->set_mesh_size(o.mesh_size);
  out->set_refine_surface(!o.keep_surface);
}

void ToProto(const fecheck::FeCheckReport& r, v1::FeCheckReport* out) {
  ToProto(r.options, out->mutable_options());
  SolidToProto(r.original, out->mutable_input());
  SolidToProto(r.simplified, out->mutable_output());
}

fecheck::FeCheckReport FromProto(const v1::FeCheckReport& in) {
  fecheck::FeCheckReport r;
  r.options = OptionsOf(in.options());
  r.original = SolidFromProto(in.input());
  r.simplified = SolidFromProto(in.output());
  return r;
}

}  // namespace femsimp::wire
