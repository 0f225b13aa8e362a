#include "client/security_flags.h"

namespace femsimp::cli {

void AddSecurityFlags(flags::FlagSet& set, SecurityFlags* f) {
  set.Switch("--tls", "connect with TLS, verifying the server with the system's CA roots", &f->tls);
  set.String("--tls-ca-file", "FILE", "connect with TLS, verifying the server with this PEM CA",
             &f->tls_ca_file);
  set.String("--tls-cert-file", "FILE", "mutual TLS: this client's PEM certificate chain",
             &f->tls_cert_file);
  set.String("--tls-key-file", "FILE", "mutual TLS: the PEM private key of --tls-cert-file",
             &f->tls_key_file);
  set.String("--token-file", "FILE",
             "send 'authorization: Bearer TOKEN' with the token in FILE (else $FEMSIMP_TOKEN_FILE "
             "or $FEMSIMP_TOKEN)",
             &f->token_file);
}

}  // namespace femsimp::cli
