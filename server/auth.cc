#include "server/auth.h"

#include "absl/container/flat_hash_set.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "common/text_file.h"

namespace femsimp::server {

absl::StatusOr<TokenAuthenticator> TokenAuthenticator::Parse(const std::string& text,
                                                             const std::string& source) {
  TokenAuthenticator auth;
  int line_number = 0;
  for (absl::string_view line : absl::StrSplit(text, '\n')) {
    ++line_number;
    line = absl::StripAsciiWhitespace(line);
    if (line.empty() || line[0] == '#') continue;
    const std::vector<absl::string_view> fields = absl::StrSplit(line, ',');
    const auto where = [&] { return absl::StrCat(source, ":", line_number, ": "); };
    if (fields.size() < 2)
      return absl::InvalidArgumentError(
          absl::StrCat(where(), "expected 'token,tenant' (the token itself is not shown)"));
    const std::string token(absl::StripAsciiWhitespace(fields[0]));
    std::string tenant(absl::StripAsciiWhitespace(fields[1]));
    if (absl::StartsWith(tenant, "\"") && absl::EndsWith(tenant, "\"") && tenant.size() >= 2)
      tenant = tenant.substr(1, tenant.size() - 2);
    if (token.empty() || tenant.empty())
      return absl::InvalidArgumentError(absl::StrCat(where(), "empty token or tenant"));
    if (!auth.tenants_.emplace(token, tenant).second)
      return absl::InvalidArgumentError(
          absl::StrCat(where(), "a token given twice (the token itself is not shown)"));
  }
  if (auth.tenants_.empty()) return absl::InvalidArgumentError(absl::StrCat(source, ": no tokens"));
  return auth;
}

absl::StatusOr<TokenAuthenticator> TokenAuthenticator::FromFile(const std::string& path) {
  absl::StatusOr<std::string> text = ReadTextFile("--auth_tokens_file", path);
  if (!text.ok()) return text.status();
  return Parse(*text, path);
}

size_t TokenAuthenticator::tenants() const {
  absl::flat_hash_set<std::string> names;
  for (const auto& [token, tenant] : tenants_) names.insert(tenant);
  return names.size();
}

grpc::Status TokenAuthenticator::Authenticate(const grpc::ServerContext& ctx,
                                              std::string* tenant) const {
  tenant->clear();
  if (!enabled()) return grpc::Status::OK;
  const auto& metadata = ctx.client_metadata();
  const auto it = metadata.find("authorization");
  if (it == metadata.end())
    return grpc::Status(grpc::StatusCode::UNAUTHENTICATED,
                        "this server needs 'authorization: Bearer TOKEN' (femsimp: --token-file "
                        "or FEMSIMP_TOKEN)");
  const absl::string_view value(it->second.data(), it->second.size());
  constexpr absl::string_view kBearer = "Bearer ";
  const auto found = absl::StartsWithIgnoreCase(value, kBearer)
                         ? tenants_.find(value.substr(kBearer.size()))
                         : tenants_.end();
  if (found == tenants_.end())
    return grpc::Status(grpc::StatusCode::UNAUTHENTICATED, "invalid bearer token");
  *tenant = found->second;
  return grpc::Status::OK;
}

}  // namespace femsimp::server
