#include "engine/simplify.h"

namespace femsimp {

absl::StatusOr<SimplifyResult> Simplify(Mesh&, const SimplifyOptions&, const SimplifyControl&) {
  return absl::UnimplementedError("engine in progress");
}

}  // namespace femsimp
