#include "server/transport_security.h"

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "common/text_file.h"
#include "grpcpp/security/server_credentials.h"

namespace femsimp::server {
namespace {

absl::StatusOr<std::string> ReadPem(const char* flag, const std::string& path) {
  absl::StatusOr<std::string> text = ReadTextFile(flag, path);
  if (text.ok() && text->find("-----BEGIN ") == std::string::npos)
    return absl::InvalidArgumentError(absl::StrCat(flag, ": ", path, " is not a PEM file"));
  return text;
}

bool Tls(const ServerConfig& c) { return !c.tls_cert_file.empty(); }

}  // namespace

bool IsLocalAddress(const std::string& listen) {
  if (absl::StartsWith(listen, "unix:")) return true;
  const size_t colon = listen.rfind(':');
  std::string host = colon == std::string::npos ? listen : listen.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']')
    host = host.substr(1, host.size() - 2);
  return host == "localhost" || host == "::1" || absl::StartsWith(host, "127.");
}

absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> ListeningCredentials(
    const ServerConfig& c) {
  if (c.tls_cert_file.empty() != c.tls_key_file.empty())
    return absl::InvalidArgumentError(
        "--tls_cert_file and --tls_key_file: give both (the server's certificate chain and its "
        "private key) or neither");
  if (!Tls(c)) {
    if (!c.tls_client_ca_file.empty())
      return absl::InvalidArgumentError(
          "--tls_client_ca_file needs --tls_cert_file and --tls_key_file");
    if (!IsLocalAddress(c.listen) && !c.plaintext_remote)
      return absl::InvalidArgumentError(absl::StrCat(
          "--listen ", c.listen,
          " without TLS would accept meshes and tokens in clear from the network: give "
          "--tls_cert_file and --tls_key_file, listen on a loopback address, or say "
          "--plaintext_remote (e.g. behind a TLS-terminating proxy)"));
    return grpc::InsecureServerCredentials();
  }
  absl::StatusOr<std::string> cert = ReadPem("--tls_cert_file", c.tls_cert_file);
  if (!cert.ok()) return cert.status();
  absl::StatusOr<std::string> key = ReadPem("--tls_key_file", c.tls_key_file);
  if (!key.ok()) return key.status();
  grpc::SslServerCredentialsOptions options;
  options.pem_key_cert_pairs.push_back({*key, *cert});
  if (!c.tls_client_ca_file.empty()) {
    absl::StatusOr<std::string> ca = ReadPem("--tls_client_ca_file", c.tls_client_ca_file);
    if (!ca.ok()) return ca.status();
    options.pem_root_certs = *ca;
    options.client_certificate_request = GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY;
  }
  return grpc::SslServerCredentials(options);
}

std::string TransportDescription(const ServerConfig& c) {
  if (!Tls(c))
    return IsLocalAddress(c.listen) ? "plaintext (loopback only)"
                                    : "plaintext on a remote address (--plaintext_remote)";
  return c.tls_client_ca_file.empty() ? "TLS" : "mutual TLS (client certificates required)";
}

}  // namespace femsimp::server
