// The pass driver (paper section 3): cost, sort, split, remove; repeat.
#include "engine/simplify.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "absl/strings/str_cat.h"
#include "engine/cost.h"
#include "engine/coverage.h"
#include "engine/face_grid.h"
#include "engine/features.h"
#include "engine/line_coverage.h"
#include "engine/mechanics.h"
#include "engine/point_copies.h"
#include "engine/quadric.h"
#include "engine/removal_backend.h"
#include "engine/rounds.h"
#include "engine/rule.h"
#include "engine/seam_collapse.h"
#include "engine/selection.h"
#include "engine/wall_thickness.h"
#include "engine/worker_pool.h"

namespace femsimp {
namespace {

using Clock = std::chrono::steady_clock;

// A reconsideration cycle that removes at most this fraction of the vertices left ends the run.
constexpr double kTrickleFraction = 1e-4;
double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

struct Bounds {
  DVec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  double diagonal() const { return Norm(hi - lo); }
  DVec3 centre() const { return 0.5 * (lo + hi); }
};

Bounds BoundsOf(const Mesh& mesh) {
  Bounds b;
  DVec3 &lo = b.lo, &hi = b.hi;
  for (uint32_t v = 0; v < mesh.vertex_capacity(); ++v) {
    if (mesh.IsRemoved(v)) continue;
    const VertexQ& q = mesh.vertices()[v];
    lo = {std::min(lo.x, double(q.x)), std::min(lo.y, double(q.y)), std::min(lo.z, double(q.z))};
    hi = {std::max(hi.x, double(q.x)), std::max(hi.y, double(q.y)), std::max(hi.z, double(q.z))};
  }
  return b;
}

CoordinatePrecision PrecisionOf(const Bounds& b) {
  const double lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
  return PrecisionOfBox(lo, hi);
}

// The tolerance that applies, as a float no larger than it (the bounds are stored as floats).
float EffectiveTolerance(const SimplifyOptions& o, double diagonal, double* tolerance) {
  double t = o.tolerance;
  if (o.tolerance_relative > 0.0) {
    const double relative = o.tolerance_relative * diagonal;
    t = t > 0.0 ? std::min(t, relative) : relative;
  }
  *tolerance = t;
  float f = static_cast<float>(t);
  if (double(f) > t) f = std::nextafter(f, 0.0f);
  return f;
}

double MaxDeviationBound(const Mesh& mesh) {
  const FaceAttrQ* attr = mesh.face_attrs();
  double worst = 0.0;
  for (uint32_t f = 0; attr != nullptr && f < mesh.face_capacity(); ++f)
    if (!mesh.IsFaceRemoved(f)) worst = std::max(worst, double(attr[f].error));
  return worst;
}

// Decides when passes stop paying off, and when rejected vertices get another chance.
class ProgressWatch {
 public:
  explicit ProgressWatch(int reconsider_every) : every_(reconsider_every) {}

  // Whether this pass makes not-removable vertices removable again: every reconsider_every-th
  // pass, or at once after a pass that only rejected.
  bool Reconsider(int pass) {
    const bool r = reconsider_next_ || (pass > 1 && (pass - 1) % every_ == 0);
    reconsider_next_ = false;
    return r;
  }

  // Progress over the last reconsideration cycle: when a whole cycle removes (almost)
  // nothing, every vertex has had its chance in the current neighbourhoods, and further
  // passes would re-try the same candidates for a trickle of removals (or for vertices that
  // only keep losing lock races to each other).
  bool NoMoreProgress(const PassStats& stats, int pass, bool reconsidered, size_t sorted) {
    recent_removed_.push_back(stats.removed);
    if (recent_removed_.size() > static_cast<size_t>(every_))
      recent_removed_.erase(recent_removed_.begin());
    uint64_t cycle_removed = 0;
    for (uint64_t r : recent_removed_) cycle_removed += r;
    const bool full_cycle = recent_removed_.size() == static_cast<size_t>(every_);
    const uint64_t trickle = static_cast<uint64_t>(kTrickleFraction * stats.vertices_left);
    if (full_cycle && pass > every_ && cycle_removed <= trickle) return true;
    if (stats.removed == 0) {
      // Only vertices once rejected could still go, and only if they have not just been
      // reconsidered: then reconsider them at once rather than waiting for the cycle.
      const bool only_rejections = stats.lock_conflicts == 0 && stats.inconsistent == 0;
      // Vertices beyond the candidate fraction were not tried yet: they go next pass, in a
      // plain pass of their own. Reconsidering would sort the rejected ones back in front of
      // them and try the same candidates in the same neighbourhoods again.
      const bool all_tried = stats.candidates == sorted;
      if (only_rejections && all_tried && (reconsidered || pass == 1)) return true;
      reconsider_next_ = only_rejections && all_tried;
    }
    return false;
  }

 private:
  const int every_;
  bool reconsider_next_ = false;
  std::vector<uint64_t> recent_removed_;  // per pass, the last reconsider_every passes
};

}  // namespace

absl::StatusOr<SimplifyResult> Simplify(Mesh& mesh, const SimplifyOptions& options,
                                        const SimplifyControl& control) {
  if (absl::Status s = ValidateOptions(options); !s.ok()) return s;
  const auto run_start = Clock::now();
  SimplifyResult result;
  result.input_vertices = mesh.CountLiveVertices();
  result.input_faces = mesh.CountLiveFaces();
  const auto cancelled = [&control] { return control.cancelled && control.cancelled(); };
  // The set-up reads the whole mesh a few times (a second or more for millions of faces): a
  // cancel between its steps ends the run with the mesh as it came, which needs no measuring.
  const auto cancelled_in_setup = [&] {
    if (!cancelled()) return false;
    result.stop_reason = StopReason::kCancelled;
    result.output_vertices = result.input_vertices;
    result.output_faces = result.input_faces;
    result.engine_seconds = Since(run_start);
    return true;
  };

  RemovalBudget budget;
  budget.alive.store(static_cast<int64_t>(result.input_vertices));
  if (options.target_vertices > 0)
    budget.target = static_cast<int64_t>(options.target_vertices);
  else if (options.ratio > 0.0)
    budget.target = std::max<int64_t>(
        1, static_cast<int64_t>(std::ceil(options.ratio * double(result.input_vertices))));

  // Fidelity set-up (docs/FIDELITY.md): features, tolerance, mechanical reference values.
  // A closed surface bounds a solid; so do the parts of an assembly, whose sheets are open.
  const bool closed = IsClosed(mesh);
  const bool solid = closed || !mesh.sides().empty();
  WorkerPool pool(options.threads);
  const FeatureSummary features = MarkFeatures(mesh, options.feature_angle_deg, cancelled, &pool);
  if (cancelled_in_setup()) return result;
  result.feature_edges = features.feature_edges;
  result.corner_vertices = features.corner_vertices;
  const Bounds bounds = BoundsOf(mesh);
  const double diagonal = bounds.diagonal();
  result.coordinates = PrecisionOf(bounds);
  RuleSetup setup;
  setup.cos_feature = std::cos(options.feature_angle_deg * std::numbers::pi / 180.0);
  setup.tolerance = EffectiveTolerance(options, diagonal, &result.tolerance_abs);
  setup.fields = static_cast<int>(mesh.field_names().size());
  setup.closed = solid;
  setup.diagonal = diagonal;
  const bool quadric = options.cost == CostKind::kQuadric;
  if (setup.tolerance > 0.0f) mesh.EnsureFaceAttrs();
  if (quadric) InitQuadrics(mesh);
  const GroupIndex groups(mesh);
  setup.groups = &groups;
  const PointCopies point_copies(mesh);
  setup.point_copies = &point_copies;
  setup.seam_vertices = mesh.locked_flags();
  // Second moments about the input's centroid, measured first about the box's centre (near the
  // part, so that no large terms cancel).
  const MassProperties measured = MeasureMass(mesh, solid, bounds.centre());
  const std::vector<double> part_volumes = MeasurePartVolumes(mesh, bounds.centre());
  setup.sides = &mesh.sides();
  setup.part_volumes = &part_volumes;
  setup.mass_origin = measured.measure != 0.0 ? measured.centroid() : bounds.centre();
  const MassProperties mass_before =
      MovedSecondMoment(measured, bounds.centre(), setup.mass_origin);
  // Positions are relative to the mesh's origin; the centroid is reported where the file has it.
  const DVec3 origin{mesh.origin()[0], mesh.origin()[1], mesh.origin()[2]};
  result.input_mass = Summarize(mass_before, solid, setup.mass_origin);
  result.input_mass.centroid += origin;
  result.input_mass.area = SurfaceArea(mesh);
  const FieldResultants fields_before = MeasureFields(mesh, groups);
  setup.mass = &mass_before;
  setup.resultants = &fields_before;
  if (cancelled_in_setup()) return result;
  if (options.max_wall_share > 0.0 && closed && setup.tolerance > 0.0f) {
    const std::optional<WallLimits> walls = SetWallLimits(
        mesh, options.max_wall_share, setup.tolerance, measured.measure > 0.0, &pool, cancelled);
    if (cancelled_in_setup()) return result;  // walls is empty only when cancelled
    result.wall_limited_share = walls->limited_area_share;
    result.thinnest_wall = walls->thinnest == kNoWall ? 0.0 : walls->thinnest;
    setup.wall_limits = true;
  }
  std::optional<FaceGrid> face_grid;
  if (!options.allow_self_intersections)
    setup.face_grid = &face_grid.emplace(mesh, cancelled, &pool);
  if (cancelled_in_setup()) return result;
  std::optional<Coverage> coverage;
  std::optional<LineCoverage> lines;
  if (options.deviation_check == DeviationCheck::kMeasured && setup.tolerance > 0.0f) {
    setup.coverage = &coverage.emplace(mesh, setup.tolerance, setup.wall_limits);
    setup.lines = &lines.emplace(mesh, setup.tolerance);
  }
  const RuleSet rules = RuleSet::Build(options, setup);

  std::unique_ptr<VertexCost> cost;
  if (quadric)
    cost = std::make_unique<QuadricCost>(mesh.quadrics());
  else if (options.cost == CostKind::kDeviation && setup.tolerance > 0.0f)
    cost = std::make_unique<DeviationCost>(mesh.face_attrs(), setup.tolerance);
  else
    cost = std::make_unique<GaussianCurvatureCost>();
  const KernelConfig kernel{&rules, quadric, options.placement == Placement::kOptimal,
                            !options.periodic_retry};
  std::unique_ptr<RemovalBackend> backend;
  if (options.backend == Backend::kCell) {
    absl::StatusOr<std::unique_ptr<RemovalBackend>> cell =
        MakeCellBackend(mesh, kernel, options.cell);
    if (!cell.ok()) return cell.status();
    backend = *std::move(cell);
  } else {
    backend = MakeNativeBackend(mesh, kernel, pool);
  }

  // Assemblies: seam points slide along their seams between passes (every copy at once).
  std::optional<SeamCollapser> seams;
  if (!point_copies.empty())
    seams.emplace(mesh, point_copies, rules, quadric, face_grid ? &*face_grid : nullptr,
                  kernel.requeue_changed);
  bool seams_moved = false;  // the host changed the mesh since the back end's last phase

  std::optional<RoundScheduler> rounds;
  if (options.schedule == Schedule::kDeterministic)
    rounds.emplace(mesh, pool, face_grid ? &*face_grid : nullptr, rules, kernel.placement,
                   control.check_kept_boxes);

  CandidateSelection selection(mesh, pool, *cost, rounds.has_value(), options.periodic_retry);
  result.stop_reason = StopReason::kMaxPasses;
  ProgressWatch watch(options.reconsider_every);
  for (int pass = 1; pass <= options.max_passes; ++pass) {
    if (budget.target > 0 && budget.alive.load() <= budget.target) {
      result.stop_reason = StopReason::kTargetReached;
      break;
    }
    if (cancelled()) {
      result.stop_reason = StopReason::kCancelled;
      break;
    }
    const auto pass_start = Clock::now();
    PassStats stats;
    stats.pass = pass;
    bool reconsider = watch.Reconsider(pass);
    if (face_grid && pass > 1) face_grid->Refresh(mesh, cancelled);
    // Select and order: every removable vertex with its cost, in cost order.
    size_t looked = 0, merged = 0;
    const auto select = [&] {
      std::vector<uint32_t> ids = selection.Select(reconsider, cancelled, &stats.busy_seconds);
      looked += selection.looked();
      if (selection.merged()) merged += selection.looked();
      return ids;
    };
    std::vector<uint32_t> sorted = select();
    // No vertex is left to try: the refused ones get their retry now, and when none is due
    // either (every one was refused in the fan it still has) the run is over.
    if (sorted.empty() && !reconsider && !cancelled()) {
      reconsider = true;
      sorted = select();
    }
    if (cancelled()) {  // the index or the order may be half made: the pass does not start
      result.stop_reason = StopReason::kCancelled;
      break;
    }
    if (sorted.empty()) {
      result.stop_reason = StopReason::kNoProgress;
      break;
    }
    if (control.on_removal_start) control.on_removal_start(pass);
    // The lowest-cost share are this pass's candidates, split over the contexts.
    stats.candidates = static_cast<uint64_t>(
        std::ceil(options.candidate_fraction * static_cast<double>(sorted.size())));
    std::atomic<bool> stop{false};
    budget.stop.store(false);
    const std::function<bool()> no_cancel;
    RemovalPhase phase{sorted.data(), stats.candidates,
                       sorted.size(), &budget,
                       &stop,         control.cancelled ? &control.cancelled : &no_cancel};
    phase.requeued = selection.requeued();
    phase.looked = looked;
    phase.merged = merged;
    phase.fresh_caches = seams_moved;
    phase.order = sorted.data();
    // Remove: each context runs the kernel on its candidates.
    if (absl::Status s =
            rounds ? rounds->RunPass(*backend, phase, stats) : backend->RunRemoval(phase, stats);
        !s.ok())
      return s;
    seams_moved = false;
    if (seams && !stop.load() && !budget.stop.load() && !cancelled()) {
      const SeamCollapser::SweepResult swept = seams->Sweep(budget);
      stats.seam_points_removed = swept.points;
      selection.requeued()->insert(selection.requeued()->end(), swept.requeued.begin(),
                                   swept.requeued.end());
      stats.removed += swept.vertices;
      seams_moved = swept.points > 0;
    }
    result.modeled_cycles += stats.modeled_pass_cycles;
    stats.vertices_left = static_cast<uint64_t>(budget.alive.load());
    stats.seconds = Since(pass_start);
    result.busy_seconds += stats.busy_seconds;
    result.passes.push_back(stats);
    if (control.on_pass) control.on_pass(result.passes.back());
    if (stop.load() && !budget.stop.load()) {
      result.stop_reason = StopReason::kCancelled;
      break;
    }
    if (budget.target > 0 && budget.alive.load() <= budget.target) {
      result.stop_reason = StopReason::kTargetReached;
      break;
    }
    if (watch.NoMoreProgress(stats, pass, reconsider, sorted.size())) {
      result.stop_reason = StopReason::kNoProgress;
      break;
    }
  }
  if (result.stop_reason == StopReason::kNoProgress || result.stop_reason == StopReason::kMaxPasses)
    for (auto p = result.passes.rbegin(); p != result.passes.rend(); ++p) {
      const auto most = std::max_element(p->rejections.begin(), p->rejections.end());
      if (*most == 0) continue;
      result.limiting_rule = static_cast<Reject>(most - p->rejections.begin());
      break;
    }
  // What the measured check's commits built holds every input point within the tolerance.
  if (coverage)
    if (absl::Status s = coverage->Audit(); !s.ok()) return s;
  if (lines)
    if (absl::Status s = lines->Audit(); !s.ok()) return s;
  result.output_vertices = mesh.CountLiveVertices();
  result.output_faces = mesh.CountLiveFaces();
  result.deviation_bound = MaxDeviationBound(mesh);
  const MassProperties mass_after = MeasureMass(mesh, solid, setup.mass_origin);
  result.output_mass = Summarize(mass_after, solid, setup.mass_origin);
  const std::vector<double> part_volumes_after = MeasurePartVolumes(mesh, bounds.centre());
  for (size_t i = 0; i < part_volumes.size(); ++i)
    result.parts.push_back({part_volumes[i], part_volumes_after[i]});
  result.output_mass.centroid += origin;
  result.output_mass.area = SurfaceArea(mesh);
  result.inertia_change = PrincipalMomentChange(result.input_mass, result.output_mass);
  if (solid && mass_before.measure != 0.0)
    result.volume_change = (mass_after.measure - mass_before.measure) / mass_before.measure;
  if (mass_before.measure != 0.0 && mass_after.measure != 0.0 && diagonal > 0.0)
    result.centroid_shift = Norm(mass_after.centroid() - mass_before.centroid()) / diagonal;
  result.max_field_change = WorstFieldChange(fields_before, MeasureFields(mesh, groups));
  result.engine_seconds = Since(run_start);
  return result;
}

}  // namespace femsimp
