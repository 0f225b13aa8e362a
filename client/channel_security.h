// The credentials and the bearer token a client's security flags (client/security_flags.h) and
// its environment name, for MakeChannel (client/remote_call.h).
#pragma once

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "client/security_flags.h"
#include "grpcpp/security/credentials.h"

namespace femsimp::cli {

// The credentials and token the flags and the environment name, files read; plaintext and no
// token when nothing is given.
struct ChannelSecurity {
  std::shared_ptr<grpc::ChannelCredentials> credentials;  // null: plaintext
  std::string token;                                      // empty: none sent
};
absl::StatusOr<ChannelSecurity> ResolveSecurity(const SecurityFlags& flags);

}  // namespace femsimp::cli
