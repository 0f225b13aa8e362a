// Mesh validity, written once. What a triangle soup must hold to be simplified (Mesh::Build runs
// CheckSoup, then checks the manifold conditions as it links the half-edges; the readers share
// RepeatsVertex); the topology figures of a soup and the check of an output against its input
// (femsimp-load --verify, the tests); the half-edge invariants of a built or simplified mesh
// (the tests).
#pragma once

#include <cstdint>
#include <string>

#include "absl/status/status.h"
#include "engine/mesh.h"
#include "engine/raw_mesh.h"

namespace femsimp {

// A triangle that names a vertex twice.
inline bool RepeatsVertex(const uint32_t* t) {
  return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}

// The soup's arrays agree (counts, face groups and fields), it is not empty and fits 32-bit
// indices, every coordinate and field value is finite, every face names three distinct vertices
// in range and has a non-zero area. InvalidArgument naming the first face or vertex that fails.
absl::Status CheckSoup(const RawMesh& raw);

// The zero-area test of CheckSoup (and of the repair stage, so that both decide alike): twice
// the area at most 1e-12 of the longest edge squared.
bool IsZeroArea(const float* a, const float* b, const float* c);
// The distance of the corner opposite the longest edge from that edge's line (0 when all three
// corners coincide): the repair stage's needle test against the weld tolerance.
double HeightOverLongestEdge(const float* a, const float* b, const float* c);

// Topology of a triangle soup, counted over the vertices that faces use.
struct SoupTopology {
  int64_t vertices = 0, edges = 0, faces = 0;
  int64_t boundary_edges = 0;
  int64_t components = 0;  // edge-connected groups of faces
  int64_t euler() const { return vertices - edges + faces; }
};

SoupTopology TopologyOf(const RawMesh& mesh);

// The output passes the engine's input validation (Mesh::Build), is not larger than the input,
// and keeps its topology: same Euler characteristic and components, closed stays closed.
// DataLoss with a message that says what differs.
absl::Status CheckOutput(const SoupTopology& input, const RawMesh& output);

// Every live face's half-edges: twins mutual and reversed, targets live; every live vertex's
// outgoing half-edge leaves it from a live face, and on a boundary has no twin; every live
// vertex is used by a face. Returns "" or a description of the first violation.
std::string HalfEdgeInvariantViolation(const Mesh& mesh);

}  // namespace femsimp
