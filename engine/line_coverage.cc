#include "engine/line_coverage.h"

#include <algorithm>

#include "absl/strings/str_format.h"
#include "engine/triangle_distance.h"

namespace femsimp {
namespace {

std::pair<uint32_t, uint32_t> Ordered(std::pair<uint32_t, uint32_t> e) {
  return e.first < e.second ? e : std::pair{e.second, e.first};
}

}  // namespace

LineCoverage::LineCoverage(const Mesh& mesh, double tolerance)
    : held_(mesh.vertex_capacity()),
      // Below the tolerance by far more than the rounding of the distances: never above it.
      tolerance2_(tolerance * (1 - 1e-9) * tolerance * (1 - 1e-9)) {
  const HalfEdgeQ* h = mesh.halfedges();
  const VertexQ* v = mesh.vertices();
  for (uint32_t e = 0; e < mesh.halfedge_capacity(); ++e) {
    if ((h[e].flags & kFaceRemoved) || !(h[e].flags & kFeatureEdge)) continue;
    if (h[e].twin != kNone && h[e].twin < e) continue;  // each edge once
    const uint32_t a = h[Prev(e)].target, b = h[e].target;
    const uint32_t segment = static_cast<uint32_t>(from_.size());
    from_.push_back({v[a].x, v[a].y, v[a].z});
    to_.push_back({v[b].x, v[b].y, v[b].z});
    from_id_.push_back(a);
    to_id_.push_back(b);
    held_[std::min(a, b)].push_back({std::max(a, b), LinePiece{segment, 0, 0}});
  }
}

void LineCoverage::Ends(const LinePiece& piece, DVec3* a, DVec3* b) const {
  const DVec3 from = from_[piece.segment], along = to_[piece.segment] - from;
  const double step = 1.0 / static_cast<double>(1u << piece.level);
  *a = from + (piece.index * step) * along;
  *b = from + ((piece.index + 1) * step) * along;
}

bool LineCoverage::Judge(LinePlan* plan, uint64_t* work) const {
  plan->given.clear();
  plan->pending.clear();
  for (int k = 0; k < plan->old_count; ++k) {
    const auto [low, high] = Ordered(plan->old_edges[k]);
    for (const Held& held : held_[low])
      if (held.other == high) plan->pending.push_back(held.piece);
  }
  while (!plan->pending.empty()) {
    if (++*work > kMaxWork) return false;
    const LinePiece piece = plan->pending.back();
    plan->pending.pop_back();
    DVec3 a, b;
    Ends(piece, &a, &b);
    int taker = -1;
    for (int k = 0; k < plan->fresh_count && taker < 0; ++k)
      if (SquaredDistanceToSegment(a, plan->fresh_from[k], plan->fresh_to[k]) <= tolerance2_ &&
          SquaredDistanceToSegment(b, plan->fresh_from[k], plan->fresh_to[k]) <= tolerance2_)
        taker = k;
    if (taker >= 0) {
      plan->given.push_back({taker, piece});
      continue;
    }
    if (piece.level == kMaxLevel) return false;
    const uint16_t level = static_cast<uint16_t>(piece.level + 1);
    const uint16_t index = static_cast<uint16_t>(2 * piece.index);
    plan->pending.push_back({piece.segment, level, static_cast<uint16_t>(index + 1)});
    plan->pending.push_back({piece.segment, level, index});
  }
  return true;
}

void LineCoverage::Apply(const LinePlan& plan) {
  for (int k = 0; k < plan.old_count; ++k) {
    // Not a structured binding: clang before 16 cannot capture one in a lambda.
    const std::pair<uint32_t, uint32_t> edge = Ordered(plan.old_edges[k]);
    const uint32_t high = edge.second;
    std::vector<Held>& list = held_[edge.first];
    list.erase(std::remove_if(list.begin(), list.end(),
                              [high](const Held& held) { return held.other == high; }),
               list.end());
  }
  for (const auto& [k, piece] : plan.given) {
    const auto [low, high] = Ordered(plan.fresh_edges[k]);
    held_[low].push_back({high, piece});
  }
}

absl::Status LineCoverage::Audit() const {
  // Each piece covers 2^(kMaxLevel - level) of the 2^kMaxLevel units of its edge.
  std::vector<uint32_t> units(from_.size(), 0);
  for (const std::vector<Held>& list : held_)
    for (const Held& held : list) units[held.piece.segment] += 1u << (kMaxLevel - held.piece.level);
  for (size_t s = 0; s < units.size(); ++s)
    if (units[s] != 1u << kMaxLevel)
      return absl::InternalError(absl::StrFormat(
          "measured check: the input feature edge from vertex %u (%g, %g, %g) to vertex %u "
          "(%g, %g, %g) is held %g times over, not once",
          from_id_[s], from_[s].x, from_[s].y, from_[s].z, to_id_[s], to_[s].x, to_[s].y, to_[s].z,
          static_cast<double>(units[s]) / (1u << kMaxLevel)));
  return absl::OkStatus();
}

}  // namespace femsimp
