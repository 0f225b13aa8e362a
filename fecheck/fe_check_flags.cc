#include "fecheck/fe_check_flags.h"

namespace femsimp::fecheck {

void AddFeCheckFlags(flags::FlagSet& set, FeCheckOptions* o) {
  set.Number({.name = "--youngs-modulus",
              .metavar = "PA",
              .help = "Young's modulus of the material",
              .range = kModulusRange,
              .unit = "Pa",
              .default_text = "2.1e11, steel"},
             &o->material.youngs_modulus);
  set.Number({.name = "--poisson-ratio",
              .metavar = "NU",
              .help = "Poisson's ratio of the material",
              .range = kPoissonRange,
              .default_text = "0.3"},
             &o->material.poisson_ratio);
  set.Number({.name = "--density",
              .metavar = "RHO",
              .help = "density of the material",
              .range = kDensityRange,
              .unit = "kg/m^3",
              .default_text = "7850"},
             &o->material.density);
  set.Number({.name = "--unit-scale",
              .metavar = "S",
              .help = "metres per model unit (0.001: the meshes are in millimetres)",
              .range = kUnitScaleRange,
              .default_text = "1"},
             &o->unit_scale);
  set.Number({.name = "--modes",
              .metavar = "N",
              .help = "non-rigid eigenfrequencies compared",
              .kind = flags::NumberKind::kInteger,
              .range = kModesRange,
              .default_text = "6"},
             &o->modes);
  set.Number({.name = "--mesh-size",
              .metavar = "F",
              .help = "largest tetrahedron inside both solids, as an edge length relative to the "
                      "original's bounding-box diagonal (the same bound for both, so that their "
                      "discretisation errors compare)",
              .kind = flags::NumberKind::kFraction,
              .range = kMeshSizeRange,
              .zero_means = "none: the surfaces alone decide",
              .default_text = "0.05"},
             &o->mesh_size);
  set.Switch("--refine-surface",
             "let tetgen add points on the surfaces (not -Y): the geometry stays, and a coarse "
             "surface meshes as finely as --mesh-size asks",
             [o] { o->keep_surface = false; });
  set.Number({.name = "--fe-threads",
              .metavar = "N",
              .help = "CalculiX's threads",
              .kind = flags::NumberKind::kInteger,
              .range = kThreadsRange,
              .default_text = "1"},
             &o->threads);
}

}  // namespace femsimp::fecheck
