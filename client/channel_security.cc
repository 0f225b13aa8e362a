#include "client/channel_security.h"

#include <cstdlib>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "common/text_file.h"

namespace femsimp::cli {

absl::StatusOr<ChannelSecurity> ResolveSecurity(const SecurityFlags& f) {
  ChannelSecurity s;
  if (f.tls_cert_file.empty() != f.tls_key_file.empty())
    return absl::InvalidArgumentError("--tls-cert-file and --tls-key-file: give both or neither");
  if (f.tls || !f.tls_ca_file.empty() || !f.tls_cert_file.empty()) {
    grpc::SslCredentialsOptions options;
    if (!f.tls_ca_file.empty()) {
      absl::StatusOr<std::string> ca = ReadTextFile("--tls-ca-file", f.tls_ca_file);
      if (!ca.ok()) return ca.status();
      options.pem_root_certs = *ca;
    }
    if (!f.tls_cert_file.empty()) {
      absl::StatusOr<std::string> cert = ReadTextFile("--tls-cert-file", f.tls_cert_file);
      if (!cert.ok()) return cert.status();
      absl::StatusOr<std::string> key = ReadTextFile("--tls-key-file", f.tls_key_file);
      if (!key.ok()) return key.status();
      options.pem_cert_chain = *cert;
      options.pem_private_key = *key;
    }
    s.credentials = grpc::SslCredentials(options);
  }
  std::string token_file = f.token_file;
  const char* from = "--token-file";
  if (token_file.empty() && std::getenv("FEMSIMP_TOKEN_FILE") != nullptr) {
    token_file = std::getenv("FEMSIMP_TOKEN_FILE");
    from = "FEMSIMP_TOKEN_FILE";
  }
  if (!token_file.empty()) {
    absl::StatusOr<std::string> token = ReadTextFile(from, token_file);
    if (!token.ok()) return token.status();
    s.token = std::string(absl::StripAsciiWhitespace(*token));
    if (s.token.empty())
      return absl::InvalidArgumentError(absl::StrCat(from, ": ", token_file, " holds no token"));
  } else if (const char* token = std::getenv("FEMSIMP_TOKEN"); token != nullptr) {
    s.token = std::string(absl::StripAsciiWhitespace(token));
  }
  return s;
}

}  // namespace femsimp::cli
