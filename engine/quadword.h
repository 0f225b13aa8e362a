// The paper's storage unit: every vertex and every half-edge is one naturally aligned 16-byte
// quadword, so a reader on any back end sees either the old or the new element, never a mix
// of two writers (each quadword has at most one writer at a time, see kernel.h).
#pragma once

#include <cstdint>

namespace femsimp {

inline constexpr uint32_t kNone = 0xFFFFFFFFu;  // no twin (boundary) / no half-edge

struct alignas(16) VertexQ {
  float x, y, z;
  uint32_t out;  // an outgoing half-edge; on a boundary vertex, the one whose twin is kNone
};

// Half-edge h belongs to face h / 3; next(h) and prev(h) are implicit in the index.
struct alignas(16) HalfEdgeQ {
  uint32_t target;  // vertex the half-edge points to
  uint32_t twin;    // opposite half-edge, kNone on a boundary edge
  uint32_t group;   // face attribute word: the face group id (same on the face's three)
  uint32_t flags;   // kFaceRemoved once the face is collapsed away
};

inline constexpr uint32_t kFaceRemoved = 1u;
// On both half-edges of a feature edge: a boundary, a group border, or a dihedral angle above
// the feature angle. Set before the passes; a collapse that joins two edges ORs their bits.
inline constexpr uint32_t kFeatureEdge = 2u;
// The face's entry in Mesh::sides() (the parts of an assembly on its two sides) sits in the
// flags' high bits, the same on its three half-edges; 0 on a mesh without parts.
inline constexpr int kSidesShift = 8;
inline constexpr uint32_t kMaxSides = 1u << (32 - kSidesShift);

// Side data per face (two quadwords), present when a tolerance or face fields are asked for:
// how far the face's points moved from the original surface (docs/FIDELITY.md: a bound on the
// length, and a box holding the displacement vectors in 16-bit steps of the run's tolerance /
// 2^14), the face's field values, and the face's own tolerance under the wall rule
// (engine/rules/wall_share.cc; 0: none, the run's). Guarded like the face's half-edges.
struct alignas(16) FaceAttrQ {
  float error;
  float field[3];
  int16_t moved_lo[3];
  int16_t moved_hi[3];
  float limit;
};

// Side data per vertex for the quadric cost: the Garland-Heckbert quadric (upper triangle of the
// 4x4 symmetric matrix, 10 floats), accumulated onto the survivor of each collapse.
struct alignas(16) QuadricQ {
  float q[10];
  float pad[2];
};

static_assert(sizeof(VertexQ) == 16 && alignof(VertexQ) == 16);
static_assert(sizeof(HalfEdgeQ) == 16 && alignof(HalfEdgeQ) == 16);
static_assert(sizeof(FaceAttrQ) == 32 && sizeof(QuadricQ) == 48);

inline uint32_t FaceOf(uint32_t h) { return h / 3; }
inline uint32_t Next(uint32_t h) { return h % 3 == 2 ? h - 2 : h + 1; }
inline uint32_t Prev(uint32_t h) { return h % 3 == 0 ? h + 2 : h - 1; }

// Per-vertex status word, changed only atomically. The lock bit is set on top of the state
// so that unlocking restores whether the vertex was removable.
enum VertexState : uint32_t {
  kRemovable = 0,
  kNotRemovable = 1,
  kRemoved = 2,
  kFixed = 3,  // a feature corner (or end of a feature line): never removed
};
inline constexpr uint32_t kLockedBit = 0x80000000u;
inline constexpr uint32_t kStateMask = 0x3u;
// On a kNotRemovable vertex: a rule that reads beyond V's fan refused it, so the next
// reconsideration retries it (one refused by fan-local rules alone waits for its fan to change).
inline constexpr uint32_t kRetryBit = 0x4u;

}  // namespace femsimp
