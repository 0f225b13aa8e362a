// Renumbers a soup's vertices and faces along a space-filling curve (Morton order), so that a
// vertex's one-ring and its fan faces sit close together in memory. The kernel's walks are
// chains of dependent loads (vertex, half-edge, twin, next face); in input order (a mesher's or a
// subdivision's numbering) each link is a cache miss, in curve order most are hits. The
// renumbering changes ids only: the same surface, its groups, fields and locked vertices.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/raw_mesh.h"

namespace femsimp {

// Vertices in Morton order of their positions, faces in Morton order of their centroids (ties:
// the input's order, so the result depends on the soup alone). Per-face data (groups, fields)
// and per-vertex data (locked vertices, point ids) follow their elements. Returns each old
// vertex's new id, or nothing where the soup is left as it is (an index beyond the vertices, a
// per-face array of the wrong size: the checks after this refuse it, naming the input's ids).
std::vector<uint32_t> SortSpatially(RawMesh& raw);

}  // namespace femsimp
