// How the server listens (docs: README "Server"): TLS from --tls_cert_file/--tls_key_file,
// mutual TLS with --tls_client_ca_file; plaintext only on a loopback address unless
// --plaintext_remote says otherwise, so that tokens and meshes do not cross a network in clear
// by accident.
#pragma once

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "grpcpp/security/server_credentials.h"
#include "server/config.h"

namespace femsimp::server {

// Whether `listen` (HOST:PORT, [V6]:PORT or unix:PATH) can only be reached from this host.
bool IsLocalAddress(const std::string& listen);

// The listening credentials the configuration asks for, or why they cannot be had (a file that
// cannot be read, a key without its certificate, plaintext on a remote address).
absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> ListeningCredentials(
    const ServerConfig& config);

// One line for the start-up log: "TLS", "mutual TLS" or "plaintext (loopback only)".
std::string TransportDescription(const ServerConfig& config);

}  // namespace femsimp::server
