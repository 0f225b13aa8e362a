// Tenants by bearer token (--auth_tokens_file, the Kubernetes static-token-file format): each
// call names its tenant with `authorization: Bearer TOKEN`; a tenant sees, reads and cancels
// only its own jobs. Without a tokens file every call is the one tenant "".
#pragma once

#include <string>

#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "grpcpp/server_context.h"

namespace femsimp::server {

class TokenAuthenticator {
 public:
  TokenAuthenticator() = default;  // no tokens: authentication is off
  // CSV lines `token,tenant[,more fields]` (more fields, e.g. a uid and groups, are ignored);
  // blank lines and lines starting with '#' are skipped. `source` names the file in errors.
  static absl::StatusOr<TokenAuthenticator> Parse(const std::string& text,
                                                  const std::string& source);
  static absl::StatusOr<TokenAuthenticator> FromFile(const std::string& path);

  bool enabled() const { return !tenants_.empty(); }
  size_t tenants() const;
  // The caller's tenant, or UNAUTHENTICATED (the token is never echoed).
  grpc::Status Authenticate(const grpc::ServerContext& ctx, std::string* tenant) const;

 private:
  absl::flat_hash_map<std::string, std::string> tenants_;  // token -> tenant
};

}  // namespace femsimp::server
