// Public entry point of the engine: parallel simplification passes over one shared mesh.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "engine/coordinate_precision.h"
#include "engine/crossings.h"
#include "engine/inertia.h"
#include "engine/mesh.h"
#include "engine/repair.h"

namespace femsimp {

enum class Backend { kNative, kCell };

// Where the options start from: kFe, the safe finite-element defaults (a plain call bounds the
// deviation and the volume, keeps features and refuses self-intersections); kPaper, the
// paper's criteria alone (no bounds, the strict minimum angle, no intersection check), for the
// paper's benchmark. Options given explicitly override the preset's.
enum class Preset { kFe, kPaper };

// How the contexts share a pass (engine/rounds.h): kDeterministic, in rounds of collapses that
// cannot interact (the output does not depend on timing or the context count); kFree, the
// paper's scheme (every context takes its candidates as it reaches them; lock races decide).
enum class Schedule { kDeterministic, kFree };

// What orders the candidates of a pass (and, for the quadric, the collapse directions).
// kDeviation: the deviation bound already spent around the vertex (the Gaussian curvature in a
// run without a tolerance).
enum class CostKind { kGaussianCurvature, kQuadric, kDeviation };

// Where a collapse puts the vertex that stays: kEndpoint, the paper's half-edge collapse (V
// moves onto a neighbour Vd); kOptimal, a full-edge collapse where V and Vd are both free to
// move (no boundary, seam or group border; no feature line, or with the measured check both on
// one crease), V and Vd merging at the quadric-optimal point that
// keeps the volume (else at the edge's midpoint) when it passes every rule, and the half-edge
// collapse otherwise (engine/star.h).
enum class Placement { kEndpoint, kOptimal };

// How the tolerance is kept (docs/FIDELITY.md § 1): kMapped, a bound on a map from the input
// carried face by face along the run (engine/deviation.h); kMeasured, every collapse judged
// against the input itself, both ways (engine/coverage.h; native back end).
enum class DeviationCheck { kMapped, kMeasured };
const char* CostKindName(CostKind c);  // "gaussian_curvature", "quadric", "deviation"

// Why a candidate was given up (each counted per pass): the rule that refused it
// (engine/rules/rule_list.inc).
enum class Reject : int {
#define FEMSIMP_RULE(reason, name, type) reason,
#include "engine/rules/rule_list.inc"
#undef FEMSIMP_RULE
  kCount
};
const char* RejectName(Reject r);  // snake_case, stable: used in JSON, proto and metrics

struct CellOptions {
  int spes = 1;
  int ls_cache_kib = 64;          // software cache size inside each 256 KiB local store
  int ls_cache_line_bytes = 128;  // bytes a miss fetches (one DMA get)
  int spe_threads = 1;            // software-managed threads per SPE (1 = off)
  int local_store_kib = 256;
  bool reread_on_stale = true;  // dirty the lines and re-read (else skip the candidate)
};

struct SimplifyOptions {
  Preset preset = Preset::kFe;  // what the other defaults are (PresetOptions)
  // Target: keep ratio * input vertices, or target_vertices when > 0. Neither: run until the
  // criteria stop the simplification.
  double ratio = 0.0;
  uint64_t target_vertices = 0;
  int threads = 1;
  double max_normal_deviation_deg = 25.0;
  double min_angle_deg = 10.0;
  double candidate_fraction = 0.9;
  // A safety net, not a stopping rule: a run ends at its target or when passes stop removing
  // (ProgressWatch). Sliver meshes free their vertices a step a pass (the min-angle rule):
  // the 3-level Loop blade reaches 10 % in 117 passes, the 4-level one in 293.
  int max_passes = 1000;
  int reconsider_every = 3;  // not-removable vertices become candidates again every Nth pass
  // A refused vertex waits for the next reconsideration even when a collapse changes its fan
  // (the paper's form). By default it is a candidate again the next pass, and reconsideration
  // retries only the vertices a rule looking beyond V's fan refused (CollapseRule::fan_local).
  bool periodic_retry = false;
  Schedule schedule = Schedule::kDeterministic;
  bool topology_only = false;
  CostKind cost = CostKind::kDeviation;
  Placement placement = Placement::kEndpoint;
  DeviationCheck deviation_check = DeviationCheck::kMapped;

  // Fidelity (docs/FIDELITY.md). 0 turns a bound off.
  // Guaranteed two-sided (Hausdorff) deviation from the input surface, absolute and/or as a
  // fraction of the bounding-box diagonal; when both are given the smaller one applies.
  double tolerance = 0.0;
  double tolerance_relative = 0.005;
  // Edges whose dihedral angle exceeds this are feature edges; a feature line turning by more
  // than this at a vertex makes it a corner. 180 keeps only boundaries and group borders.
  double feature_angle_deg = 30.0;
  // Relative to the input volume; applies to closed meshes (an open one encloses none).
  double max_volume_change = 0.005;
  double max_centroid_shift = 0.0;  // relative to the bounding-box diagonal
  // Relative change allowed of each principal moment of inertia (of the solid, or of the
  // surface of an open mesh).
  double max_inertia_change = 0.0;
  // Closed parts: each face's tolerance at most this share of the wall thickness under it
  // (engine/wall_thickness.h, engine/rules/wall_share.cc); needs the mapped deviation check.
  double max_wall_share = 0.0;
  // Relative change allowed of each face field's resultant per group, measured against the
  // group's total absolute load (sum of |value| * area). Applies when the mesh has fields.
  double max_field_change = 0.01;
  // Collapses whose new triangles would intersect the mesh are refused unless this is set
  // (engine/rules/self_intersection.cc).
  bool allow_self_intersections = false;
  // Minimum angle: a new triangle must reach min_angle_deg (the paper's strict form); by
  // default it may also be no worse than the worst triangle it replaces, so slivers improve.
  bool strict_min_angle = false;

  Backend backend = Backend::kNative;
  CellOptions cell;
  // The repair stage before the simplification (engine/prepare.h): its mode and weld tolerance
  // are options of the table; Simplify itself does not read them.
  RepairOptions repair;
};

// The options of a preset, before any given explicitly.
SimplifyOptions PresetOptions(Preset preset);

// Checks every parameter's range; the message names the parameter and the allowed range.
absl::Status ValidateOptions(const SimplifyOptions& options);

struct CellPassCounters {
  uint64_t cache_hits = 0, cache_misses = 0;
  uint64_t stale_detected = 0, stale_reread = 0, stale_skipped = 0;
  uint64_t dma_transfers = 0, dma_bytes = 0;
  uint64_t atomic_ops = 0, thread_switches = 0;
  uint64_t busy_cycles = 0;
  uint64_t modeled_cycles = 0;  // compute + DMA stalls + atomics
  CellPassCounters& operator+=(const CellPassCounters& o) {
    cache_hits += o.cache_hits;
    cache_misses += o.cache_misses;
    stale_detected += o.stale_detected;
    stale_reread += o.stale_reread;
    stale_skipped += o.stale_skipped;
    dma_transfers += o.dma_transfers;
    dma_bytes += o.dma_bytes;
    atomic_ops += o.atomic_ops;
    thread_switches += o.thread_switches;
    busy_cycles += o.busy_cycles;
    modeled_cycles += o.modeled_cycles;
    return *this;
  }
  double hit_ratio() const {
    uint64_t n = cache_hits + cache_misses;
    return n ? static_cast<double>(cache_hits) / static_cast<double>(n) : 0.0;
  }
};

struct PassStats {
  int pass = 0;             // 1-based
  uint64_t candidates = 0;  // vertices handed to the contexts this pass
  uint64_t tried = 0;       // candidates actually attempted (before the target stopped it)
  uint64_t removed = 0;
  uint64_t lock_conflicts = 0;       // a vertex of the one-ring was locked by another context
  uint64_t inconsistent = 0;         // ring did not close or referenced a removed element
  uint64_t rounds = 0;               // deterministic schedule: rounds of non-interacting collapses
  uint64_t seam_points_removed = 0;  // assemblies: seam points slid along their seam (all copies)
  uint64_t placed = 0;  // of the removals: full-edge collapses (option placement = optimal)
  uint64_t placed_on_lines = 0;  // of those: V and Vd on one feature line, merged off it
  // Deterministic rounds: candidates' boxes kept from an earlier round of the pass instead of
  // read again (no commit since changed what they were made of).
  uint64_t boxes_kept = 0;
  std::array<uint64_t, static_cast<int>(Reject::kCount)> rejections{};
  uint64_t vertices_left = 0;
  double seconds = 0.0;       // wall time of the pass
  double busy_seconds = 0.0;  // summed over contexts (parallel speedup = busy / seconds)
  // Cell back end only.
  std::optional<CellPassCounters> cell;  // totals over SPEs
  std::vector<CellPassCounters> cell_per_spe;
  uint64_t ppe_cycles = 0;  // modeled sequential share
  // Of modeled_pass_cycles: the starts and ends of the removal runs and the rounds' fan-box
  // runs (launches and joins, or a resident program's wake-ups and reports).
  uint64_t spe_start_cycles = 0;
  uint64_t modeled_pass_cycles = 0;  // slowest SPE + PPE share
};

enum class StopReason { kTargetReached, kNoProgress, kMaxPasses, kCancelled };
const char* StopReasonName(StopReason r);

struct SimplifyResult {
  uint64_t input_vertices = 0, input_faces = 0;
  uint64_t output_vertices = 0, output_faces = 0;
  double engine_seconds = 0.0;
  double busy_seconds = 0.0;
  StopReason stop_reason = StopReason::kNoProgress;
  // When no valid collapse was left (no_progress, max_passes): the rule that refused the most
  // candidates in the last pass that refused any — what limits the run (kCount: none).
  Reject limiting_rule = Reject::kCount;
  std::vector<PassStats> passes;
  // Cell back end: modeled speedup needs the one-SPE time, so only the cycle totals are kept.
  uint64_t modeled_cycles = 0;

  // Fidelity figures of the output (docs/FIDELITY.md).
  uint64_t feature_edges = 0;    // in the input
  uint64_t corner_vertices = 0;  // fixed feature corners in the input
  double tolerance_abs = 0.0;    // the tolerance that applied (0: none)
  double deviation_bound =
      0.0;  // guaranteed Hausdorff bound reached (tracked when a tolerance is set)
  double volume_change = 0.0;     // relative, signed (closed meshes)
  double centroid_shift = 0.0;    // relative to the bounding-box diagonal
  double max_field_change = 0.0;  // worst relative resultant change over fields and groups
  // Mass properties of the input and the output, and the largest relative change of a
  // principal moment of inertia.
  MassSummary input_mass, output_mass;
  double inertia_change = 0.0;
  // The parts of an assembly that meet at seams (engine/solid_parts.h), each a solid: its
  // volume in the input and in the output. Empty for a mesh without such parts.
  struct PartVolume {
    double input = 0.0, output = 0.0;
  };
  std::vector<PartVolume> parts;
  // The wall rule (max_wall_share), when on: the share of the input's area whose tolerance the
  // walls lowered, and the thinnest wall measured (0: the rule was off or met no wall thinner
  // than tolerance / max_wall_share, where its rays stop).
  double wall_limited_share = 0.0;
  double thinnest_wall = 0.0;
  // Face pairs of the output that cross each other (engine/crossings.h). Not Simplify's: it is
  // not engine time, and the output soup is what a mesher reads, so the callers of OutputMesh
  // (the CLI, the server) fill it from the soup they write.
  SoupCrossings output_crossings;
  CoordinatePrecision coordinates;
};

struct SimplifyControl {
  std::function<void(const PassStats&)> on_pass;  // called after every pass, on the caller's thread
  // Called when a pass's removals begin (its candidates' costs computed and sorted), with the
  // pass's number, on the caller's thread.
  std::function<void(int)> on_removal_start;
  // Polled between the set-up's steps and inside the long ones, between passes and by every
  // context every 32 candidates inside one (so from several threads at once: it must be
  // thread-safe); true stops the job with the mesh still valid, and must stay true.
  std::function<bool()> cancelled;
  // A self-check for tests: the deterministic rounds read every box they keep from an earlier
  // round again and fail the run (an internal error) where the two differ.
  bool check_kept_boxes = false;
};

absl::StatusOr<SimplifyResult> Simplify(Mesh& mesh, const SimplifyOptions& options,
                                        const SimplifyControl& control = {});

}  // namespace femsimp
