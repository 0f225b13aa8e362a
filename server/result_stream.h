// Streams a job's output mesh as chunks, encoding chunk k+1 on a helper thread while chunk k is
// being written: the encoding overlaps the wire, and at most two encoded chunks exist at once
// (never a whole encoded copy of the mesh).
#pragma once

#include <functional>

#include "engine/raw_mesh.h"
#include "femsimp/v1/femsimp.pb.h"

namespace femsimp::server {

struct ChunkStreamTimes {
  double encode_seconds = 0;  // spent filling chunks (on the helper thread, overlapped)
  double write_seconds = 0;   // spent in `write` (waiting for the wire)
};

// Calls write with each chunk of `mesh` in order (wire::FillChunk's cut); stops at the first
// write that returns false and returns false then. Adds the stream's times to *times.
bool StreamMeshChunks(const RawMesh& mesh,
                      const std::function<bool(const v1::SimplifyResponse&)>& write,
                      ChunkStreamTimes* times);

}  // namespace femsimp::server
