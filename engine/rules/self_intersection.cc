// No new triangle may intersect another triangle of the mesh (or another new one). The faces
// around each new triangle come from the face index (engine/face_grid.h), whose cells over V's
// fan the check holds until the candidate is done; on commit the fan's faces move to their new
// cells. Near-touching counts as touching (engine/triangle_intersection.h), so a refusal errs
// on the safe side.
#include <algorithm>
#include <cmath>

#include "engine/face_grid.h"
#include "engine/fan_separation.h"
#include "engine/planar_retile.h"
#include "engine/rule.h"

namespace femsimp {
namespace {

constexpr uint32_t kCyclesPerTriangleTest = 60;
// The flat-face shortcut, per coordinate compare or 2D orientation test.
constexpr uint32_t kCyclesPerPlanarTest = 6;

class SelfIntersectionRule final : public CollapseRule {
 public:
  explicit SelfIntersectionRule(FaceGrid* grid) : grid_(grid) {}
  Reject reason() const override { return Reject::kSelfIntersection; }
  uint32_t stages() const override { return Stages(RuleStage::kFidelity); }
  bool keeps_state() const override { return true; }

  Verdict Check(RuleStage, CollapseProposal& p) const override {
    const Ring& fan = *p.fan;
    const bool star = p.star != nullptr;
    // A star's neighbourhood is its own (each direction has another Vd).
    if (p.cells_acquired && (p.cells_for_star != star || (star && p.cells_vd != p.star->vd_id)))
      Release(p);
    if (!p.cells_acquired) {
      if (Verdict v = HoldNeighbourhood(p); v != Verdict::kPass) return v;
    }
    // Inside a flat face the new triangles cover what the old ones did, and nothing more.
    if (!star && p.also_replaced.empty()) {
      int planar_tests = 0;
      const bool retiles = RetilesTheFanInItsPlane(fan, p.target, &planar_tests);
      p.cycles += kCyclesPerPlanarTest * planar_tests;
      if (retiles) return Verdict::kPass;
    }
    // The faces left out are apart from the new triangles only where these are one to one seen
    // along the fan's normal: a later direction that is not reads them all.
    if (!p.nearby_read)
      ReadNearby(p, /*separate=*/!star && p.also_replaced.empty());
    else if (p.nearby_separated && !p.separation->Covers(p.target))
      ReadNearby(p, false);
    PreparedTriangle fresh[kMaxStar];
    int count = 0;
    if (star) {
      for (int k = 0; k < p.star->count; ++k)
        if (p.star->survives[k]) fresh[count++] = PreparedTriangle(NewStarTriangle(*p.star, k));
    } else {
      for (int f = 0; f < fan.faces; ++f)
        if (!p.IsDeleted(f)) fresh[count++] = PreparedTriangle(NewTriangle(p, f));
    }
    // The cell back end's cycle model charges every pair tested (boxes overlapping, for the
    // faces nearby) up to the first hit, in the order new triangle by new triangle, nearby
    // faces by id: counted so whatever order they are tested in.
    uint32_t tests = 0;
    bool hit = false;
    for (int a = 0; a < count && !hit; ++a) {
      for (int b = a + 1; b < count && !hit; ++b, ++tests)
        hit = fresh[a].box.Overlaps(fresh[b].box) &&
              OverlappingTrianglesIntersect(fresh[a], fresh[b]);
      if (hit) break;
      uint32_t first_hit = kNone;  // the smallest id of a face fresh[a] meets
      uint32_t overlapping = 0;
      for (size_t k = 0; k < p.nearby.size(); ++k) {
        if (!fresh[a].box.Overlaps(p.nearby[k].box)) continue;
        ++overlapping;
        if (p.nearby_faces[k] < first_hit && OverlappingTrianglesIntersect(fresh[a], p.nearby[k]))
          first_hit = p.nearby_faces[k];
      }
      if (first_hit != kNone) {
        hit = true;
        overlapping = 0;
        for (size_t k = 0; k < p.nearby.size(); ++k)
          overlapping += p.nearby_faces[k] <= first_hit && fresh[a].box.Overlaps(p.nearby[k].box);
      }
      tests += overlapping;
    }
    p.cycles += kCyclesPerTriangleTest * tests;
    return hit ? Verdict::kReject : Verdict::kPass;
  }

  void Commit(CollapseProposal& p) const override {
    if (p.star != nullptr) return CommitStar(*p.star);
    const Ring& fan = *p.fan;
    double length_change = 0;
    int64_t face_change = 0;
    FaceGrid::FaceMove moves[kMaxRing];
    for (int f = 0; f < fan.faces; ++f) {
      const Triangle before = OldTriangle(fan, f);
      FaceGrid::FaceMove& m = moves[f];
      m.face = FaceOf(fan.out[f]);
      m.before = m.after = FaceGrid::BoxOf(before.p, 3);
      m.removed = p.IsDeleted(f);
      length_change -= Perimeter(before);
      if (m.removed) {
        --face_change;
      } else {
        const Triangle after = NewTriangle(p, f);
        m.after = FaceGrid::BoxOf(after.p, 3);
        length_change += Perimeter(after);
      }
    }
    grid_->CommitMoves({moves, static_cast<size_t>(fan.faces)}, length_change, face_change);
  }

  void Release(CollapseProposal& p) const override {
    grid_->Release(&p.held_cells);
    p.cells_acquired = false;
  }

 private:
  // The box of V's fan (V and its one-ring: every direction's new triangles lie in it), or for
  // a full-edge collapse the star's box (P stays inside it); `points` gets the fan's points.
  static FaceGrid::Box NeighbourhoodBox(const CollapseProposal& p, DVec3* points) {
    const Ring& fan = *p.fan;
    points[0] = ToD(fan.center_pos);
    for (int i = 0; i < fan.neighbours(); ++i) points[i + 1] = ToD(fan.pos[i]);
    return p.star != nullptr ? FaceGrid::Box{p.star->lo, p.star->hi}
                             : FaceGrid::BoxOf(points, fan.neighbours() + 1);
  }

  // Holds the cells over the neighbourhood's box: the commit moves the fan's faces within them.
  Verdict HoldNeighbourhood(CollapseProposal& p) const {
    DVec3 points[kMaxRing + 2];
    const FaceGrid::Hold hold = grid_->Acquire(NeighbourhoodBox(p, points), &p.held_cells);
    if (hold == FaceGrid::Hold::kBusy) return Verdict::kConflict;
    if (hold == FaceGrid::Hold::kFull) return Verdict::kReject;  // cannot prove it safe
    p.cells_acquired = true;
    p.nearby_read = false;
    p.cells_for_star = p.star != nullptr;
    p.cells_vd = p.star != nullptr ? p.star->vd_id : kNone;
    return Verdict::kPass;
  }

  // Reads the faces in the held cells once for all directions (or positions of P): those whose
  // boxes could overlap a new triangle's, but for those shown beside V's fan when `separate`.
  void ReadNearby(CollapseProposal& p, bool separate) const {
    const Ring& fan = *p.fan;
    const EdgeStar* star = p.star;
    DVec3 points[kMaxRing + 2];
    const FaceGrid::Box box = NeighbourhoodBox(p, points);
    p.nearby_read = true;
    p.nearby_separated = false;
    if (separate) {
      uint32_t ids[kMaxRing];
      for (int i = 0; i < fan.faces; ++i) ids[i] = grid_->PointId(fan.nbr[i]);
      if (p.separation == nullptr) p.separation = std::make_unique<FanSeparation>();
      p.nearby_separated = p.separation->Prepare(fan, ids) && p.separation->Covers(p.target);
      p.cycles += kCyclesPerPlanarTest * 2 * fan.faces;
    }
    const DVec3 corners[2] = {box.lo, box.hi};
    const TriangleBox reach = star != nullptr ? NewTrianglesReach(corners, 2)
                                              : NewTrianglesReach(points + 1, fan.neighbours());
    p.nearby.clear();
    p.nearby_faces.clear();
    // The cells list the faces' plain boxes: widened by the most any face's box is widened.
    const double face_slack = 12e-9 * grid_->magnitude() + 1e-30;
    const FaceGrid::Box near{reach.lo - DVec3{face_slack, face_slack, face_slack},
                             reach.hi + DVec3{face_slack, face_slack, face_slack}};
    // The fan's faces (a bit per face id modulo 64 passes most others over at once) are
    // replaced by the new triangles. The others are listed first and their corners fetched
    // ahead, so that the reads of scattered faces overlap.
    uint64_t fan_bits = 0;
    for (int f = 0; f < fan.faces; ++f) fan_bits |= uint64_t{1} << (FaceOf(fan.out[f]) & 63);
    if (star != nullptr)
      for (int k = 0; k < star->count; ++k) fan_bits |= uint64_t{1} << (star->face[k] & 63);
    grid_->ForEachFaceNear(box, p.held_cells, near, [&](uint32_t g) {
      if ((fan_bits >> (g & 63) & 1) != 0 && (star != nullptr ? InStar(*star, g) : InFan(fan, g)))
        return;
      if (!p.also_replaced.empty() &&
          std::find(p.also_replaced.begin(), p.also_replaced.end(), g) != p.also_replaced.end())
        return;
      grid_->Prefetch(g);
      p.nearby_faces.push_back(g);
    });
    for (uint32_t g : p.nearby_faces) grid_->PrefetchCorners(g);
    size_t kept = 0;
    int planar_tests = 0;
    for (uint32_t g : p.nearby_faces) {
      const Triangle t = grid_->FaceTriangle(g);
      if (p.nearby_separated && p.separation->Apart(t, &planar_tests)) continue;
      p.nearby.emplace_back(t);
      if (p.nearby.back().box.Overlaps(reach)) {
        p.nearby_faces[kept++] = g;
      } else {
        p.nearby.pop_back();
      }
    }
    p.nearby_faces.resize(kept);
    p.cycles += kCyclesPerPlanarTest * planar_tests;
  }

  // A box that holds the (widened) box of every new triangle of every direction: they use the
  // one-ring's points only (or the star's box's). A new triangle's slack is 1e-9 times the sum of
  // the magnitudes of its box's six coordinates, at most twice the ring's largest magnitudes per
  // axis; this one's is twice that, and rounding is monotonic.
  static TriangleBox NewTrianglesReach(const DVec3* ring, int n) {
    const FaceGrid::Box b = FaceGrid::BoxOf(ring, n);
    const double magnitude = std::max(std::fabs(b.lo.x), std::fabs(b.hi.x)) +
                             std::max(std::fabs(b.lo.y), std::fabs(b.hi.y)) +
                             std::max(std::fabs(b.lo.z), std::fabs(b.hi.z));
    const double slack = 4e-9 * magnitude + 1e-30;
    TriangleBox reach;
    reach.lo = b.lo - DVec3{slack, slack, slack};
    reach.hi = b.hi + DVec3{slack, slack, slack};
    return reach;
  }

  // Corners are named by their points (FaceGrid::PointId), as the face index names them: a
  // seam copy in another sheet is the same corner, where the sheets touch by design.
  Triangle OldTriangle(const Ring& fan, int f) const {
    const int g = (f + 1) % fan.neighbours();
    return Triangle{
        {ToD(fan.center_pos), ToD(fan.pos[f]), ToD(fan.pos[g])},
        {grid_->PointId(fan.center), grid_->PointId(fan.nbr[f]), grid_->PointId(fan.nbr[g])}};
  }
  Triangle NewTriangle(const CollapseProposal& p, int f) const {
    Triangle t = OldTriangle(*p.fan, f);
    t.p[0] = ToD(p.fan->pos[p.target]);
    t.id[0] = grid_->PointId(p.vd());
    return t;
  }
  Triangle OldStarTriangle(const EdgeStar& star, int k) const {
    return Triangle{
        {star.a[k], star.b[k], star.c[k]},
        {grid_->PointId(star.a_id[k]), grid_->PointId(star.b_id[k]), grid_->PointId(star.c_id[k])}};
  }
  Triangle NewStarTriangle(const EdgeStar& star, int k) const {
    Triangle t = OldStarTriangle(star, k);
    t.p[0] = star.p;
    t.id[0] = grid_->PointId(star.vd_id);
    return t;
  }

  void CommitStar(const EdgeStar& star) const {
    double length_change = 0;
    int64_t face_change = 0;
    FaceGrid::FaceMove moves[kMaxStar];
    for (int k = 0; k < star.count; ++k) {
      const Triangle before = OldStarTriangle(star, k);
      FaceGrid::FaceMove& m = moves[k];
      m.face = star.face[k];
      m.before = m.after = FaceGrid::BoxOf(before.p, 3);
      m.removed = !star.survives[k];
      length_change -= Perimeter(before);
      if (m.removed) {
        --face_change;
      } else {
        const Triangle after = NewStarTriangle(star, k);
        m.after = FaceGrid::BoxOf(after.p, 3);
        length_change += Perimeter(after);
      }
    }
    grid_->CommitMoves({moves, static_cast<size_t>(star.count)}, length_change, face_change);
  }

  static bool InStar(const EdgeStar& star, uint32_t face) {
    for (int k = 0; k < star.count; ++k)
      if (star.face[k] == face) return true;
    return false;
  }
  static double Perimeter(const Triangle& t) {
    return Norm(t.p[1] - t.p[0]) + Norm(t.p[2] - t.p[1]) + Norm(t.p[0] - t.p[2]);
  }
  static bool InFan(const Ring& fan, uint32_t face) {
    for (int f = 0; f < fan.faces; ++f)
      if (FaceOf(fan.out[f]) == face) return true;
    return false;
  }

  FaceGrid* grid_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeSelfIntersectionRule(const SimplifyOptions& o,
                                                       const RuleSetup& s) {
  if (o.allow_self_intersections || s.face_grid == nullptr) return nullptr;
  return std::make_unique<SelfIntersectionRule>(s.face_grid);
}

}  // namespace femsimp
