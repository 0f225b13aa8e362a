// What every fuzz target asserts beyond "no crash, no sanitizer report": a refusal says why.
#pragma once

#include <cstdlib>
#include <utility>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "engine/prepare.h"
#include "engine/raw_mesh.h"

namespace femsimp::fuzz {

inline void RequireMessage(const absl::Status& s) {
  if (!s.ok() && s.message().empty()) std::abort();  // every refusal says why
}

// A mesh an upload or a file gave goes on through the repair stage and Mesh::Build, as the
// server and the CLI take it: whatever it holds, the answer is a mesh or an error with a message.
// The mesh so built comes out again (seams joined, shared surfaces written once per body).
inline void Prepare(RawMesh mesh, const RepairOptions& options) {
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(std::move(mesh), options);
  RequireMessage(prepared.status());
  if (!prepared.ok()) return;
  const absl::StatusOr<RawMesh> out =
      OutputMesh(prepared->mesh, prepared->seam_map, prepared->shared_walls);
  if (!out.ok()) std::abort();  // nothing simplified: the seams cannot have changed
}

}  // namespace femsimp::fuzz
