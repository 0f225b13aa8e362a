// The flags every client shares for a server that asks for TLS and a bearer token
// (server/auth.h, server/transport_security.h); client/channel_security.h turns them into a
// channel's credentials.
#pragma once

#include <string>

#include "common/flags.h"

namespace femsimp::cli {

struct SecurityFlags {
  bool tls = false;           // verify the server with the system's roots
  std::string tls_ca_file;    // ... or with this CA (implies --tls)
  std::string tls_cert_file;  // mutual TLS: this client's certificate and key
  std::string tls_key_file;
  std::string token_file;  // else $FEMSIMP_TOKEN_FILE, else $FEMSIMP_TOKEN
  bool any() const {
    return tls || !tls_ca_file.empty() || !tls_cert_file.empty() || !tls_key_file.empty() ||
           !token_file.empty();
  }
};
void AddSecurityFlags(flags::FlagSet& set, SecurityFlags* flags);

}  // namespace femsimp::cli
