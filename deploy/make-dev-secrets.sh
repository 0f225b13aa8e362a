#!/usr/bin/env bash
# Development secrets for the deployments (compose, Kubernetes, the scale-out and container
# tests): a CA, a server certificate, a client certificate (for mutual TLS, optional there) and
# bearer tokens, made with openssl. Not for production: the CA key lies next to what it signed.
#
#   deploy/make-dev-secrets.sh [DIR]        (default deploy/secrets, ignored by git)
#
# DIR gets (mode 0700; the files 0644, because a compose secret is a bind mount of the file and
# the replicas and nginx read it as their own non-root users):
#   ca.pem ca.key                 the development CA (ECDSA P-256)
#   server.pem server.key         SANs: the compose service `femsimp`, the Kubernetes Service
#                                 `femsimp.femsimp(.svc(.cluster.local))`, localhost, 127.0.0.1
#                                 and ::1 (probes and port-forwards reach the pod on loopback)
#   client.pem client.key         CN=femsimp-client, for --tls-cert-file/--tls-key-file
#   tokens.csv                    `token,tenant` lines for --auth_tokens_file (one per tenant)
#   token-TENANT                  each tenant's token, for femsimp --token-file
#   k8s-secrets.yaml              Secrets femsimp-tls (kubernetes.io/tls: tls.crt, tls.key,
#                                 ca.crt) and femsimp-tokens (tokens.csv) in namespace femsimp,
#                                 for `kubectl apply -f`
# Environment: TENANTS (default "dev"), DAYS (validity, default 365), EXTRA_SANS (more
# subjectAltName entries, e.g. "DNS:femsimp.example.org,IP:10.0.0.5").
# An existing DIR is refused (delete it to make new secrets), so a run never half-replaces keys.
set -euo pipefail

dir=${1:-$(dirname "$0")/secrets}
tenants=${TENANTS:-dev}
days=${DAYS:-365}
sans="DNS:femsimp,DNS:femsimp.femsimp,DNS:femsimp.femsimp.svc,DNS:femsimp.femsimp.svc.cluster.local"
sans+=",DNS:localhost,IP:127.0.0.1,IP:::1${EXTRA_SANS:+,$EXTRA_SANS}"

if [ -e "$dir" ]; then
  echo "make-dev-secrets: $dir exists; remove it to make new secrets" >&2
  exit 1
fi
command -v openssl >/dev/null || { echo "make-dev-secrets: openssl not found" >&2; exit 1; }
mkdir -p "$(dirname "$dir")"
mkdir -m 0700 "$dir"
cd "$dir"
log=$(mktemp)
trap 'rm -f "$log" ./*.csr ./*.ext ./*.srl' EXIT

ec_key=(-newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes)
if ! {
  openssl req -x509 "${ec_key[@]}" -days "$days" -subj /CN=femsimp-dev-ca \
    -addext basicConstraints=critical,CA:TRUE -addext keyUsage=critical,keyCertSign,cRLSign \
    -keyout ca.key -out ca.pem
  sign() {  # sign NAME CN EXTENSIONS
    openssl req "${ec_key[@]}" -subj "/CN=$2" -keyout "$1.key" -out "$1.csr"
    printf '%s\n' "$3" >"$1.ext"
    openssl x509 -req -in "$1.csr" -CA ca.pem -CAkey ca.key -CAcreateserial -days "$days" \
      -extfile "$1.ext" -out "$1.pem"
  }
  sign server femsimp "subjectAltName=$sans
extendedKeyUsage=serverAuth"
  sign client femsimp-client "extendedKeyUsage=clientAuth"
} >"$log" 2>&1; then
  cat "$log" >&2
  echo "make-dev-secrets: openssl failed" >&2
  exit 1
fi

: >tokens.csv
for t in $tenants; do
  [[ "$t" =~ ^[A-Za-z0-9_.-]+$ ]] || { echo "make-dev-secrets: bad tenant name '$t'" >&2; exit 1; }
  token=$(openssl rand -hex 32)  # 256 random bits
  printf '%s,%s\n' "$token" "$t" >>tokens.csv
  printf '%s\n' "$token" >"token-$t"
done
chmod 0644 ./*

b64() { base64 -w0 "$1"; }
cat >k8s-secrets.yaml <<EOF
# Made by deploy/make-dev-secrets.sh: kubectl apply -f k8s-secrets.yaml
apiVersion: v1
kind: Secret
metadata:
  name: femsimp-tls
  namespace: femsimp
  labels:
    app.kubernetes.io/name: femsimp
type: kubernetes.io/tls
data:
  tls.crt: $(b64 server.pem)
  tls.key: $(b64 server.key)
  ca.crt: $(b64 ca.pem)
---
apiVersion: v1
kind: Secret
metadata:
  name: femsimp-tokens
  namespace: femsimp
  labels:
    app.kubernetes.io/name: femsimp
type: Opaque
data:
  tokens.csv: $(b64 tokens.csv)
EOF
chmod 0600 k8s-secrets.yaml ca.key
echo "make-dev-secrets: wrote $(pwd): CA, server (${sans}), client certificate, tokens for: $tenants"
