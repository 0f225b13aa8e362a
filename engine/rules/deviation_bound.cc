// The guaranteed deviation bound (docs/FIDELITY.md, engine/deviation.h): every surviving fan
// face's bound after the collapse stays within the tolerance. Proposes the new bounds and
// displacement boxes, and the faces' own tolerances (FaceAttrQ::limit) that the map carries for
// the wall rule.
#include <algorithm>
#include <cmath>

#include "engine/deviation.h"
#include "engine/rule.h"

namespace femsimp {
namespace {

class DeviationBoundRule final : public CollapseRule {
 public:
  explicit DeviationBoundRule(float tolerance)
      : tolerance_(tolerance), unit_(double(tolerance) / kBoxSteps) {}
  Reject reason() const override { return Reject::kTolerance; }
  // kScreen: the bound's cheap refusals (LayOutDirection), before the kernel reads Vd's
  // ring for the topology rules; most refused directions stop there.
  uint32_t stages() const override { return Stages(RuleStage::kScreen, RuleStage::kFidelity); }
  bool reads_face_attrs() const override { return true; }
  bool fan_local() const override { return true; }
  // A star on a line is laid out so that its old line goes onto the new one
  // (BoundStarDeviation): the map keeps sending the input's lines onto the output's.
  bool holds_placed_lines() const override { return true; }

  Verdict Check(RuleStage stage, CollapseProposal& p) const override {
    if (p.star != nullptr) return stage == RuleStage::kScreen ? Verdict::kPass : CheckStar(p);
    const int nf = p.fan->faces;
    // Off the stack: an SPE software thread's is small (56 KiB, engine/cell_backend.cc), and
    // 64 of these are 3.5 KiB. Per OS thread: the software threads of an SPE switch only at
    // DMA waits, never inside this check.
    thread_local Displacement new_moved[kMaxRing];
    Kept& kept = Layout(p);
    const Displacement* old_moved = kept.old_moved;
    int work = 0;
    // The screen lays the direction out; the fidelity check right after it reuses that.
    const bool screened = stage == RuleStage::kFidelity && kept.direction_target == p.target;
    if (!screened) {
      kept.direction_target = -1;
      if (!LayOutDirection(*p.fan, kept.fan, p.target, p.line_other, old_moved, tolerance_,
                           &kept.direction, &work)) {
        p.cycles += static_cast<uint32_t>(28 * work);
        return Verdict::kReject;
      }
      kept.direction_target = p.target;
    }
    if (stage == RuleStage::kScreen) return Verdict::kPass;
    const bool bounded = BoundDeviation(*p.fan, kept.fan, kept.direction, p.target, old_moved,
                                        tolerance_, new_moved, &work);
    p.cycles += static_cast<uint32_t>(28 * work);
    if (!bounded) return Verdict::kReject;
    for (int f = 0; f < nf; ++f)
      if (!p.IsDeleted(f) && !Pack(new_moved[f], &p.new_attr[f])) return Verdict::kReject;
    return Verdict::kPass;
  }

 private:
  // V's fan laid out and its faces' displacements unpacked once per candidate (every direction
  // and both stages share them; the side quadwords do not change under the candidate's locks),
  // and the last direction the screen passed. Per OS thread like the buffers above; another SPE
  // software thread may have laid out its own fan between two checks, which the serial tells
  // (0: a proposal not made by a kernel, laid out every time).
  struct Kept {
    uint64_t serial = 0;  // 0: nothing kept
    FanLayout fan;
    Displacement old_moved[kMaxRing];
    int direction_target = -1;  // -1: none kept
    DirectionLayout direction;
  };
  Kept& Layout(const CollapseProposal& p) const {
    thread_local Kept kept;
    if (p.fan_serial == 0 || kept.serial != p.fan_serial) {
      LayOutFan(*p.fan, &kept.fan);
      for (int f = 0; f < p.fan->faces; ++f) kept.old_moved[f] = Unpack(p.fan_attr[f]);
      kept.serial = p.fan_serial;
      kept.direction_target = -1;
    }
    return kept;
  }

  // The box travels in FaceAttrQ as 16-bit multiples of unit_, rounded outwards; a box within
  // the tolerance spans at most half their range.
  static constexpr double kBoxSteps = 16384.0;

  Displacement Unpack(const FaceAttrQ& a) const {
    Displacement d;
    d.bound = a.error;
    d.lo = {a.moved_lo[0] * unit_, a.moved_lo[1] * unit_, a.moved_lo[2] * unit_};
    d.hi = {a.moved_hi[0] * unit_, a.moved_hi[1] * unit_, a.moved_hi[2] * unit_};
    if (a.limit > 0.0f) d.limit = a.limit;
    return d;
  }

  // False when the face would be out of tolerance.
  bool Pack(const Displacement& d, FaceAttrQ* a) const {
    const float bound = std::nextafter(static_cast<float>(d.bound), 1e30f);  // never below
    if (!(bound <= tolerance_)) return false;
    a->error = bound;
    a->limit = std::isinf(d.limit) ? 0.0f : static_cast<float>(d.limit);  // a least of floats
    const double lo[3] = {d.lo.x, d.lo.y, d.lo.z}, hi[3] = {d.hi.x, d.hi.y, d.hi.z};
    for (int i = 0; i < 3; ++i) {
      a->moved_lo[i] =
          static_cast<int16_t>(std::clamp(std::floor(lo[i] / unit_), -32768.0, 32767.0));
      a->moved_hi[i] =
          static_cast<int16_t>(std::clamp(std::ceil(hi[i] / unit_), -32768.0, 32767.0));
    }
    return true;
  }

  Verdict CheckStar(CollapseProposal& p) const {
    const EdgeStar& star = *p.star;
    thread_local Displacement old_moved[kMaxStar], new_moved[kMaxStar];  // as in Check
    for (int k = 0; k < star.count; ++k)
      old_moved[k] = Unpack(k < star.fan_faces ? p.fan_attr[k] : p.extra_attr[k - star.fan_faces]);
    int work = 0;
    const bool bounded = BoundStarDeviation(star, old_moved, new_moved, &work);
    p.cycles += static_cast<uint32_t>(28 * work);
    if (!bounded) return Verdict::kReject;
    for (int k = 0; k < star.count; ++k) {
      if (!star.survives[k]) continue;
      FaceAttrQ& attr = k < star.fan_faces ? p.new_attr[k] : p.new_extra_attr[k - star.fan_faces];
      if (!Pack(new_moved[k], &attr)) return Verdict::kReject;
    }
    return Verdict::kPass;
  }

  float tolerance_;
  double unit_;
};

}  // namespace

// engine/rules/measured_deviation.cc: the same criterion checked against the input itself.
std::unique_ptr<CollapseRule> MakeMeasuredDeviationRule(const RuleSetup& s);

std::unique_ptr<CollapseRule> MakeDeviationBoundRule(const SimplifyOptions& o, const RuleSetup& s) {
  if (!(s.tolerance > 0.0f)) return nullptr;
  if (o.deviation_check == DeviationCheck::kMeasured) return MakeMeasuredDeviationRule(s);
  return std::make_unique<DeviationBoundRule>(s.tolerance);
}

}  // namespace femsimp
