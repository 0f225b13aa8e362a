// The FE check (fecheck/fe_check.h) on the wire: JobSpec.fe_check_options and Result.fe_check,
// both ways; shared by the server and the remote client.
#pragma once

#include "absl/status/statusor.h"
#include "fecheck/fe_check.h"
#include "femsimp/v1/femsimp.pb.h"

namespace femsimp::wire {

// Unset or 0 fields take the defaults; ValidateFeCheckOptions' message when one is out of range.
absl::StatusOr<fecheck::FeCheckOptions> FeCheckOptionsFromProto(const v1::FeCheckOptions& in);
// Every field set (the options as applied).
void ToProto(const fecheck::FeCheckOptions& o, v1::FeCheckOptions* out);

void ToProto(const fecheck::FeCheckReport& r, v1::FeCheckReport* out);
// Options out of range (from a newer or broken server) are kept as sent: this only reports.
fecheck::FeCheckReport FromProto(const v1::FeCheckReport& in);

}  // namespace femsimp::wire
