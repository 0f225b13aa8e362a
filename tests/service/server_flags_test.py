#!/usr/bin/python3
"""femsimp-server --helpfull lists every flag (the TLS, token and limit flags of issue 15 among
them), and the README's server-flags paragraph names each one, so no limit goes undocumented.

  server_flags_test.py SERVER_BIN README
"""
import re
import subprocess
import sys

server_bin, readme = sys.argv[1], sys.argv[2]
out = subprocess.run([server_bin, "--helpfull"], capture_output=True, text=True)
if out.returncode != 0:
    sys.exit(f"femsimp-server --helpfull exited {out.returncode}: {out.stderr}")
flags = re.findall(r"^  (--[a-z_]+)", out.stdout, re.M)
required = ["--tls_cert_file", "--tls_key_file", "--tls_client_ca_file", "--auth_tokens_file",
            "--max_jobs_per_tenant", "--memory_budget_mib", "--upload_idle_seconds",
            "--upload_deadline_seconds", "--result_idle_seconds", "--max_spes",
            "--max_cell_local_store_mib", "--max_vertices", "--max_faces", "--queue_capacity"]
problems = [f"--helpfull does not list {f}" for f in required if f not in flags]
text = open(readme).read()
start = text.index("Server flags (`femsimp-server --help`)")
paragraph = text[start:text.index("\n\n", start)]
problems += [f"the README's server flags do not name {f}" for f in flags
             if f != "--help" and not re.search(re.escape(f"`{f}") + r"[` =]", paragraph)]
for p in problems:
    print("FAILED:", p)
print(f"{len(flags)} flags in --helpfull, {len(problems)} problems")
sys.exit(1 if problems else 0)
