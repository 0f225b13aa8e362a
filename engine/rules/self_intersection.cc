// No new triangle may intersect another triangle of the mesh (or another new one). The faces
// around each new triangle come from the face index (engine/face_grid.h), whose cells over V's
// fan the check holds until the candidate is done; on commit the fan's faces move to their new
// cells. Near-touching counts as touching (engine/triangle_intersection.h), so a refusal errs
// on the safe side.
#include <algorithm>

#include "engine/face_grid.h"
#include "engine/rule.h"

namespace femsimp {
namespace {

constexpr uint32_t kCyclesPerTriangleTest = 60;

class SelfIntersectionRule final : public CollapseRule {
 public:
  explicit SelfIntersectionRule(FaceGrid* grid) : grid_(grid) {}
  Reject reason() const override { return Reject::kSelfIntersection; }
  uint32_t stages() const override { return Stages(RuleStage::kFidelity); }
  bool keeps_state() const override { return true; }

  Verdict Check(RuleStage, CollapseProposal& p) const override {
    const Ring& fan = *p.fan;
    if (!p.cells_acquired) {
      if (Verdict v = HoldNeighbourhood(p); v != Verdict::kPass) return v;
    }
    Triangle fresh[kMaxRing];
    int count = 0;
    for (int f = 0; f < fan.faces; ++f)
      if (!p.IsDeleted(f)) fresh[count++] = NewTriangle(p, f);
    uint32_t tests = 0;
    bool hit = false;
    for (int a = 0; a < count && !hit; ++a) {
      for (int b = a + 1; b < count && !hit; ++b, ++tests)
        hit = TrianglesIntersect(fresh[a], fresh[b]);
      const TriangleBox box(fresh[a]);
      for (size_t k = 0; k < p.nearby.size() && !hit; ++k) {
        if (!box.Overlaps(p.nearby_boxes[k])) continue;
        ++tests;
        hit = OverlappingTrianglesIntersect(fresh[a], p.nearby[k]);
      }
    }
    p.cycles += kCyclesPerTriangleTest * tests;
    return hit ? Verdict::kReject : Verdict::kPass;
  }

  void Commit(CollapseProposal& p) const override {
    const Ring& fan = *p.fan;
    for (int f = 0; f < fan.faces; ++f) {
      const Triangle before = OldTriangle(fan, f);
      const FaceGrid::Box old_box = FaceGrid::BoxOf(before.p, 3);
      const uint32_t face = FaceOf(fan.out[f]);
      if (p.IsDeleted(f)) {
        grid_->Move(face, old_box, nullptr);
      } else {
        const Triangle after = NewTriangle(p, f);
        const FaceGrid::Box new_box = FaceGrid::BoxOf(after.p, 3);
        grid_->Move(face, old_box, &new_box);
      }
    }
  }

  void Release(CollapseProposal& p) const override {
    grid_->Release(&p.held_cells);
    p.cells_acquired = false;
  }

 private:
  // Holds the cells over V's fan (V and its one-ring: every direction's new triangles lie in
  // its box) and reads the faces there once for all directions.
  Verdict HoldNeighbourhood(CollapseProposal& p) const {
    const Ring& fan = *p.fan;
    DVec3 points[kMaxRing + 2];
    points[0] = ToD(fan.center_pos);
    for (int i = 0; i < fan.neighbours(); ++i) points[i + 1] = ToD(fan.pos[i]);
    const FaceGrid::Box box = FaceGrid::BoxOf(points, fan.neighbours() + 1);
    const FaceGrid::Hold hold = grid_->Acquire(box, &p.held_cells);
    if (hold == FaceGrid::Hold::kBusy) return Verdict::kConflict;
    if (hold == FaceGrid::Hold::kFull) return Verdict::kReject;  // cannot prove it safe
    p.cells_acquired = true;
    std::vector<uint32_t>& ids = p.nearby_faces;
    ids.clear();
    grid_->ForEachFace(box, p.held_cells, [&](uint32_t g) {
      ids.push_back(g);
      return true;
    });
    std::sort(ids.begin(), ids.end());
    // A face listed in several cells is read once; the fan's faces are replaced by the new
    // triangles.
    p.nearby.clear();
    p.nearby_boxes.clear();
    for (size_t i = 0; i < ids.size();) {
      size_t j = i;
      while (j < ids.size() && ids[j] == ids[i]) ++j;
      if (!InFan(fan, ids[i])) {
        p.nearby.push_back(grid_->FaceTriangle(ids[i]));
        p.nearby_boxes.emplace_back(p.nearby.back());
      }
      i = j;
    }
    return Verdict::kPass;
  }

  static Triangle OldTriangle(const Ring& fan, int f) {
    const int g = (f + 1) % fan.neighbours();
    return Triangle{{ToD(fan.center_pos), ToD(fan.pos[f]), ToD(fan.pos[g])},
                    {fan.center, fan.nbr[f], fan.nbr[g]}};
  }
  static Triangle NewTriangle(const CollapseProposal& p, int f) {
    Triangle t = OldTriangle(*p.fan, f);
    t.p[0] = ToD(p.fan->pos[p.target]);
    t.id[0] = p.vd();
    return t;
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
