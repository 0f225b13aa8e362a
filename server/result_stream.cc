#include "server/result_stream.h"

#include <future>
#include <memory>

#include "proto/wire.h"
#include "server/stopwatch.h"

namespace femsimp::server {
namespace {

struct Encoded {
  std::unique_ptr<v1::SimplifyResponse> response;
  double seconds = 0;
};

Encoded Encode(const RawMesh& mesh, size_t k) {
  Stopwatch time;
  auto response = std::make_unique<v1::SimplifyResponse>();
  wire::FillChunk(mesh, k, response->mutable_chunk());
  return {std::move(response), time.seconds()};
}

}  // namespace

bool StreamMeshChunks(const RawMesh& mesh,
                      const std::function<bool(const v1::SimplifyResponse&)>& write,
                      ChunkStreamTimes* times) {
  const size_t count = wire::ChunkCount(mesh);
  if (count == 0) return true;
  Encoded current = Encode(mesh, 0);
  for (size_t k = 0; k < count; ++k) {
    times->encode_seconds += current.seconds;
    std::future<Encoded> ahead;
    if (k + 1 < count) ahead = std::async(std::launch::async, Encode, std::cref(mesh), k + 1);
    Stopwatch write_time;
    const bool ok = write(*current.response);
    times->write_seconds += write_time.seconds();
    // The helper is joined on every path: it reads `mesh`, which the caller may free next.
    if (ahead.valid()) current = ahead.get();
    if (!ok) return false;
  }
  return true;
}

}  // namespace femsimp::server
