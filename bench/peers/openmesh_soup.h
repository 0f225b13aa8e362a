// Soups into OpenMesh's TriMesh and back, for the benchmarks' OpenMesh Decimater runs.
#pragma once

#include "engine/io/openmesh.h"
#include "engine/raw_mesh.h"

namespace femsimp::bench {

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// `in` as a TriMesh, with face normals (the Decimater's normal-flipping module needs them).
void ToTriMesh(const RawMesh& in, TriMesh& mesh);

// The mesh's vertices and faces as a soup, in OpenMesh's order (after garbage_collection).
RawMesh FromTriMesh(const TriMesh& mesh);

}  // namespace femsimp::bench
