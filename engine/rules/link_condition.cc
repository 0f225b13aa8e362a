// The link condition: V and Vd may share no neighbour but the vertices opposite their edge, so
// that the collapse joins no vertices already connected — no duplicate face, no pinched vertex,
// no change of genus. In an assembly cut into sheets (engine/seams.h) it must hold of the mesh
// the sheets are joined into again, where the copies of one point are one vertex: neighbours
// are compared as points (a sheet may hold two copies of one point, a pinched vertex split
// apart), and a vertex W joined to a seam vertex Vd anew may not be joined to any other copy of
// Vd's point already: in its own sheet (W's ring) or, when W is a seam point too, in any sheet
// (the rings of Vd's other copies). Otherwise the joined edge would have four faces, or a seam
// between them would gain two.
//
// The other copies' rings lie beyond the one-rings the kernel locks. A deterministic round
// never changes them meanwhile: a winner that would is next to a copy of Vd's point, at Vd's
// position, so its box overlaps this candidate's. The free schedule has no such guard: there a
// race may go unseen, and the rejoin's check (engine/seams.h) then fails the job.
#include "engine/rule.h"

namespace femsimp {
namespace {

class LinkConditionRule final : public CollapseRule {
 public:
  LinkConditionRule(const PointCopies* copies, const uint8_t* seam_vertices)
      : copies_(copies), seam_(seam_vertices) {}
  Reject reason() const override { return Reject::kLink; }
  uint32_t stages() const override { return Stages(RuleStage::kTopology); }
  Verdict Check(RuleStage, CollapseProposal& p) const override {
    const Ring& fan = *p.fan;
    const Ring& other = *p.target_fan;
    const auto joined_already = [&](uint32_t w) {
      return w == p.opposite[0] || (p.deleted == 2 && w == p.opposite[1]);
    };
    for (int a = 0; a < other.neighbours(); ++a) {
      const uint32_t w = other.nbr[a];
      if (w == fan.center || joined_already(w)) continue;
      const uint32_t point = PointOf(w);
      for (int b = 0; b < fan.neighbours(); ++b)
        if (PointOf(fan.nbr[b]) == point) return Verdict::kReject;
    }
    const uint32_t vd = fan.nbr[p.target];
    if (seam_ == nullptr || !seam_[vd]) return Verdict::kPass;
    for (int b = 0; b < fan.neighbours(); ++b) {
      const uint32_t w = fan.nbr[b];
      if (b == p.target || joined_already(w)) continue;
      const Verdict v = seam_[w] ? SeamPointsJoined(p, vd, w) : JoinedToCopy(p, w, vd);
      if (v != Verdict::kPass) return v;
    }
    return Verdict::kPass;
  }

 private:
  uint32_t PointOf(uint32_t v) const { return copies_ == nullptr ? v : copies_->PointOf(v); }

  // Whether u's ring holds a copy of `point` other than `except` (kReject), or cannot be read.
  Verdict RingHolds(CollapseProposal& p, uint32_t u, uint32_t point, uint32_t except) const {
    uint32_t around[kMaxRing + 1];
    const int count = p.reader->Neighbours(u, around);
    if (count < 0) return Verdict::kStale;
    if (count > kMaxRing + 1) return Verdict::kReject;  // cannot tell
    for (int k = 0; k < count; ++k)
      if (around[k] != except && PointOf(around[k]) == point) return Verdict::kReject;
    return Verdict::kPass;
  }

  // W (not a seam vertex: it has no other copy) joined to another copy of Vd's point.
  Verdict JoinedToCopy(CollapseProposal& p, uint32_t w, uint32_t vd) const {
    return RingHolds(p, w, PointOf(vd), vd);
  }

  // Another copy of Vd's point joined to W's point. The seam edge a seam point's compound
  // collapse makes (engine/seam_collapse.h) passes: every copy's collapse is checked before any
  // is made.
  Verdict SeamPointsJoined(CollapseProposal& p, uint32_t vd, uint32_t w) const {
    for (const uint32_t u : copies_->Of(PointOf(vd)))
      if (u != vd)
        if (const Verdict v = RingHolds(p, u, PointOf(w), kNone); v != Verdict::kPass) return v;
    return Verdict::kPass;
  }

  const PointCopies* copies_;  // null: every vertex its own point
  const uint8_t* seam_;        // Mesh::locked_flags, or null: no seams
};

}  // namespace

std::unique_ptr<CollapseRule> MakeLinkConditionRule(const SimplifyOptions&,
                                                    const RuleSetup& setup) {
  return std::make_unique<LinkConditionRule>(setup.point_copies, setup.seam_vertices);
}

}  // namespace femsimp
