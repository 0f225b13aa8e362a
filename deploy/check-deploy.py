#!/usr/bin/python3
"""Offline checks of the deployment files, for CI (ctest deploy_manifests).

kubectl cannot validate without a cluster here (`kubectl apply --dry-run=client` still asks an
API server for discovery and the OpenAPI schema), so this renders deploy/k8s with
`kubectl kustomize` and checks every object against the Kubernetes API types of Debian's
python3-kubernetes (unknown or misspelt fields, wrong types, missing required fields), then
checks what ties the files together: selectors and labels, ports, probes, the ConfigMap's flags
(accepted by the real femsimp-server), resources against those flags, the HPA and the PDB. The
compose stack is checked with docker-compose and its flags against the ConfigMap's, Prometheus'
config with promtool, nginx's with `nginx -t`, and the Dockerfile against the Deployment.
Transport security everywhere (issue 15): no --plaintext_remote in any file, TLS and a tokens
file from mounted Secrets (compose secrets), probes over TLS, a NetworkPolicy; the Secrets that
deploy/make-dev-secrets.sh writes are checked against the API types and the mounts, and the
real server is started with them.

  deploy/check-deploy.py --server-bin build/server/femsimp-server --client-bin build/client/femsimp

Exit codes: 0 passed, 1 a check failed, 77 a required tool is missing (kubectl, python3-kubernetes).
"""
import argparse
import base64
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import yaml

DEPLOY = os.path.dirname(os.path.abspath(__file__))
problems = []


def problem(msg):
    problems.append(msg)
    print("FAILED:", msg, file=sys.stderr)


def ok(msg):
    print("ok:", msg)


def skip(msg):
    print("check-deploy: SKIP:", msg)
    sys.exit(77)


try:
    import kubernetes.client as k8s
except ImportError:
    skip("python3-kubernetes is not installed")

# Kinds by apiVersion. The library speaks Kubernetes 1.22: autoscaling/v2 (GA in 1.23) has the
# schema of v2beta2.
MODELS = {
    ("v1", "Namespace"): "V1Namespace",
    ("v1", "ConfigMap"): "V1ConfigMap",
    ("v1", "Service"): "V1Service",
    ("apps/v1", "Deployment"): "V1Deployment",
    ("autoscaling/v2", "HorizontalPodAutoscaler"): "V2beta2HorizontalPodAutoscaler",
    ("policy/v1", "PodDisruptionBudget"): "V1PodDisruptionBudget",
    ("networking.k8s.io/v1", "NetworkPolicy"): "V1NetworkPolicy",
    ("v1", "Secret"): "V1Secret",
}
# What the deployments must carry (flags of femsimp-server).
TLS_FLAGS = ("tls_cert_file", "tls_key_file", "auth_tokens_file")
# Fields newer than the library: gRPC probes (Kubernetes 1.24, GA in 1.27).
NEWER_FIELDS = {"V1Probe": {"grpc": {"port": int, "service": str}}}


def check_fields(value, type_name, path):
    """Every key must be a field of type_name, recursively, with a value of the right type."""
    if type_name in ("object",):
        return
    if type_name.startswith("list["):
        if not isinstance(value, list):
            problem(f"{path}: expected a list")
            return
        for i, item in enumerate(value):
            check_fields(item, type_name[5:-1], f"{path}[{i}]")
        return
    if type_name.startswith("dict("):
        if not isinstance(value, dict):
            problem(f"{path}: expected a map")
            return
        inner = type_name[type_name.index(",") + 1:-1].strip()
        for k, v in value.items():
            check_fields(v, inner, f"{path}.{k}")
        return
    scalars = {"str": str, "int": int, "bool": bool, "float": (int, float), "datetime": str}
    if type_name in scalars:
        if not isinstance(value, scalars[type_name]) or (type_name == "int" and isinstance(value, bool)):
            problem(f"{path}: {value!r} is not a {type_name}")
        return
    model = getattr(k8s, type_name)
    if not isinstance(value, dict):
        problem(f"{path}: expected a {type_name} map")
        return
    fields = {json_name: model.openapi_types[py] for py, json_name in model.attribute_map.items()}
    newer = NEWER_FIELDS.get(type_name, {})
    for key, v in value.items():
        if key in fields:
            check_fields(v, fields[key], f"{path}.{key}")
        elif key in newer:
            for sub, sub_v in v.items():
                if sub not in newer[key] or not isinstance(sub_v, newer[key][sub]):
                    problem(f"{path}.{key}.{sub}: not a field of {key}, or of the wrong type")
        else:
            problem(f"{path}.{key}: no such field in {type_name}")


def check_required(obj, model_name, path):
    """The library's deserializer raises on a missing required field."""
    client = k8s.ApiClient()
    try:
        client._ApiClient__deserialize(obj, model_name)  # pylint: disable=protected-access
    except (ValueError, TypeError) as e:
        problem(f"{path}: {e}")


def make_dev_secrets(tmp):
    """deploy/make-dev-secrets.sh into tmp/dev: the files, and its Kubernetes Secrets."""
    out_dir = os.path.join(tmp, "dev")
    out = subprocess.run([os.path.join(DEPLOY, "make-dev-secrets.sh"), out_dir],
                         capture_output=True, text=True)
    if out.returncode != 0:
        problem(f"make-dev-secrets.sh failed: {out.stderr.strip()}")
        return None, []
    ok("make-dev-secrets.sh makes a CA, server and client certificates, tokens, k8s Secrets")
    with open(os.path.join(out_dir, "k8s-secrets.yaml")) as f:
        return out_dir, [d for d in yaml.safe_load_all(f) if d]


def materialize_mounts(secrets, mounts, volumes, root):
    """Writes each mounted Secret's keys under root + its mountPath, as the kubelet would."""
    by_name = {s["metadata"]["name"]: s for s in secrets}
    for vname, path in mounts.items():
        secret_name = volumes.get(vname, {}).get("secret", {}).get("secretName")
        if not secret_name:
            continue
        if secret_name not in by_name:
            problem(f"volume {vname} mounts Secret {secret_name}, which make-dev-secrets.sh does not make")
            continue
        os.makedirs(root + path, exist_ok=True)
        for key, b64 in by_name[secret_name]["data"].items():
            with open(os.path.join(root + path, key), "wb") as f:
                f.write(base64.b64decode(b64))


def rendered_objects():
    kubectl = shutil.which("kubectl")
    if not kubectl:
        skip("kubectl is not installed (Debian: kubernetes-client)")
    env = dict(os.environ, KUBECONFIG=os.devnull)
    out = subprocess.run([kubectl, "kustomize", os.path.join(DEPLOY, "k8s")], env=env,
                         capture_output=True, text=True)
    if out.returncode != 0:
        problem(f"kubectl kustomize deploy/k8s: {out.stderr.strip()}")
        return []
    ok("kubectl kustomize deploy/k8s renders")
    return [d for d in yaml.safe_load_all(out.stdout) if d]


def parse_flags(lines):
    flags = {}
    for line in lines:
        line = line.split(" #", 1)[0].strip()  # a compose list item's trailing comment
        if not line or line.startswith("#"):  # the flagfile's comments
            continue
        m = re.fullmatch(r"--([a-z_]+)(?:=(.*))?", line)
        if not m:
            problem(f"flag line {line!r} is not --name=value or a --switch")
            continue
        flags[m.group(1)] = m.group(2) if m.group(2) is not None else "true"
    return flags


def run_server_with_flagfile(server_bin, client_bin, flag_text, root, probe):
    """The real femsimp-server must accept the ConfigMap's flags with the Secrets mounted (under
    root), answer the Deployment's probe command over TLS, and stop on SIGTERM."""
    with tempfile.TemporaryDirectory() as tmp:
        flagfile = os.path.join(tmp, "femsimp.flags")
        with open(flagfile, "w") as f:
            f.write(re.sub(r"=(/etc/femsimp/)", lambda m: "=" + root + m.group(1), flag_text))
        log_path = os.path.join(tmp, "server.log")
        with open(log_path, "w") as log:
            proc = subprocess.Popen([server_bin, f"--flagfile={flagfile}",
                                     "--listen=127.0.0.1:0", "--metrics_listen=127.0.0.1:0"],
                                    stdout=log, stderr=subprocess.STDOUT)
        try:
            port = None
            for _ in range(300):
                text = open(log_path).read()
                m = re.search(r"listening on \S+ \(port (\d+)\)", text)
                if m:
                    port = m.group(1)
                    break
                if proc.poll() is not None:
                    break
                time.sleep(0.1)
            if not port:
                problem(f"femsimp-server rejected the ConfigMap's flags: {open(log_path).read()[-500:]}")
                return
            # The probe as the Deployment runs it, on this port and with the mounts under root.
            cmd = [client_bin] + [re.sub(r":\d+$", f":{port}", a) if a.startswith("127.0.0.1:")
                                  else root + a if a.startswith("/etc/femsimp/") else a
                                  for a in probe[1:]]
            health = subprocess.run(cmd, capture_output=True, text=True)
            if health.returncode != 0:
                problem(f"the probe does not find femsimp-server with the ConfigMap's flags "
                        f"SERVING: {health.stdout}{health.stderr}")
            plain = subprocess.run([client_bin, "health", "--server", f"127.0.0.1:{port}",
                                    "--timeout", "2"], capture_output=True, text=True)
            if plain.returncode == 0:
                problem("femsimp-server with the ConfigMap's flags answers plaintext calls")
            proc.send_signal(signal.SIGTERM)
            rc = proc.wait(timeout=60)
            if rc != 0:
                problem(f"femsimp-server exited {rc} on SIGTERM")
            else:
                ok("femsimp-server accepts the ConfigMap's flags with the dev Secrets mounted, "
                   "answers the probe over TLS (not plaintext), stops on SIGTERM")
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()


def quantity_cpu(q):
    q = str(q)
    return float(q[:-1]) / 1000 if q.endswith("m") else float(q)


def quantity_bytes(q):
    units = {"Ki": 2**10, "Mi": 2**20, "Gi": 2**30, "k": 1e3, "M": 1e6, "G": 1e9, "g": 1e9, "m": 1e6}
    m = re.fullmatch(r"([0-9.]+)([A-Za-z]*)", str(q))
    return float(m.group(1)) * units.get(m.group(2), 1)


def check_k8s(objects, args, dev_secrets, tmp):
    by_kind = {}
    if any(o.get("kind") == "Secret" for o in objects):
        problem("deploy/k8s renders a Secret: keys do not belong in git")
    objects = objects + dev_secrets
    for obj in objects:
        key = (obj.get("apiVersion"), obj.get("kind"))
        name = f"{key[1]}/{obj.get('metadata', {}).get('name')}"
        if key not in MODELS:
            problem(f"{name}: {key[0]} {key[1]} is not a kind this check knows")
            continue
        check_fields(obj, MODELS[key], name)
        check_required(obj, MODELS[key], name)
        by_kind.setdefault(key[1], []).append(obj)
    if problems:
        return None
    ok(f"{len(objects)} objects match the Kubernetes API types ({', '.join(sorted(by_kind))})")
    for kind in ("Namespace", "ConfigMap", "Deployment", "Service", "HorizontalPodAutoscaler",
                 "PodDisruptionBudget", "NetworkPolicy"):
        if kind not in by_kind:
            problem(f"no {kind} in deploy/k8s")
    if problems:
        return None

    dep = by_kind["Deployment"][0]
    pod = dep["spec"]["template"]
    labels = pod["metadata"]["labels"]
    container = pod["spec"]["containers"][0]

    def selects(selector, what):
        if not selector.items() <= labels.items():
            problem(f"{what} selector {selector} does not match the pod labels {labels}")

    selects(dep["spec"]["selector"]["matchLabels"], "Deployment")
    svc = by_kind["Service"][0]
    selects(svc["spec"]["selector"], "Service")
    pdb = by_kind["PodDisruptionBudget"][0]
    selects(pdb["spec"]["selector"]["matchLabels"], "PodDisruptionBudget")
    if svc["spec"].get("clusterIP") != "None":
        problem("the Service is not headless (clients balance over the pod addresses)")

    ports = {p["name"]: p["containerPort"] for p in container["ports"]}
    for p in svc["spec"]["ports"]:
        if p["targetPort"] not in ports:
            problem(f"Service port {p['name']} targets {p['targetPort']}, not a container port")
    # The kubelet's gRPC probe has no TLS: `femsimp health` over TLS on the grpc port instead.
    probe_cmd = None
    for probe in ("readinessProbe", "livenessProbe"):
        cmd = container.get(probe, {}).get("exec", {}).get("command", [])
        want = ["/usr/local/bin/femsimp", "health", "--server", f"127.0.0.1:{ports.get('grpc')}"]
        if cmd[:4] != want or "--tls-ca-file" not in cmd:
            problem(f"{probe} is not `femsimp health --server 127.0.0.1:GRPC_PORT --tls-ca-file ...`")
        else:
            probe_cmd = cmd
    ann = pod["metadata"].get("annotations", {})
    if ann.get("prometheus.io/scrape") != "true" or int(ann.get("prometheus.io/port", 0)) != ports.get("metrics"):
        problem("the Prometheus annotations do not point at the metrics port")

    cm = by_kind["ConfigMap"][0]
    mounts = {m["name"]: m["mountPath"] for m in container.get("volumeMounts", [])}
    volumes = {v["name"]: v for v in pod["spec"].get("volumes", [])}
    flagfile_arg = [a for a in container.get("args", []) if a.startswith("--flagfile=")]
    if not flagfile_arg:
        problem("the container does not read a --flagfile")
        return None
    flagfile = flagfile_arg[0].split("=", 1)[1]
    found = False
    for vname, path in mounts.items():
        vol = volumes.get(vname, {})
        if vol.get("configMap", {}).get("name") == cm["metadata"]["name"] and \
                os.path.dirname(flagfile) == path.rstrip("/"):
            found = os.path.basename(flagfile) in cm["data"]
    if not found:
        problem(f"{flagfile} is not a key of ConfigMap {cm['metadata']['name']} mounted there")
        return None
    flag_text = cm["data"][os.path.basename(flagfile)]
    flags = parse_flags(flag_text.splitlines())
    check_tls_flags(flags, "the ConfigMap")
    # Every file the flags and the probe name lies in a mounted Secret and is one of its keys.
    secret_mounts = {path.rstrip("/"): volumes[v]["secret"]["secretName"]
                     for v, path in mounts.items() if "secret" in volumes.get(v, {})}
    secrets = {o["metadata"]["name"]: o for o in dev_secrets}
    probe_ca = probe_cmd[probe_cmd.index("--tls-ca-file") + 1] if probe_cmd else None
    for what, path in [(f"--{f}", flags.get(f)) for f in TLS_FLAGS] + [("the probe's CA", probe_ca)]:
        if not path:
            continue
        name = secret_mounts.get(os.path.dirname(path))
        if not name:
            problem(f"{what} {path} is not in a mounted Secret")
        elif os.path.basename(path) not in secrets.get(name, {}).get("data", {}):
            problem(f"{what} {path}: Secret {name} has no key {os.path.basename(path)}")
    for v in volumes.values():
        if "secret" not in v:
            continue
        mode = v["secret"].get("defaultMode", 0o644)
        if mode & 0o007:
            problem(f"Secret volume {v['name']} is readable by others (defaultMode {mode:o})")
    root = os.path.join(tmp, "pod")
    materialize_mounts(dev_secrets, mounts, volumes, root)
    if probe_cmd:
        run_server_with_flagfile(args.server_bin, args.client_bin, flag_text, root, probe_cmd)

    # The NetworkPolicy: the pods, both directions, ingress only to the pod's ports.
    netpol = by_kind["NetworkPolicy"][0]
    selects(netpol["spec"]["podSelector"]["matchLabels"], "NetworkPolicy")
    if set(netpol["spec"].get("policyTypes", [])) != {"Ingress", "Egress"}:
        problem("the NetworkPolicy does not restrict both ingress and egress")
    allowed = set()
    for rule in netpol["spec"].get("ingress", []):
        if not rule.get("from") or not rule.get("ports"):
            problem("a NetworkPolicy ingress rule admits any source or any port")
        for p in rule.get("ports", []):
            port = p.get("port")
            allowed.add(port if port in ports else {v: k for k, v in ports.items()}.get(port))
    if allowed != set(ports):
        problem(f"the NetworkPolicy admits {sorted(map(str, allowed))}, the pod serves {sorted(ports)}")
    # Set explicitly: the defaults follow the host's cores, not the pod's CPU limit.
    missing = [f for f in ("workers", "threads_per_job", "queue_capacity", "max_faces",
                           "grace_period_seconds", "listen", "metrics_listen") if f not in flags]
    if missing:
        problem(f"the ConfigMap does not set --{', --'.join(missing)}")
        return None
    for name, port_name in (("listen", "grpc"), ("metrics_listen", "metrics")):
        if not flags.get(name, "").endswith(f":{ports[port_name]}"):
            problem(f"--{name}={flags.get(name)} does not listen on the {port_name} port")

    # Resources against what the flags let a replica do.
    res = container["resources"]
    cpu_limit = quantity_cpu(res["limits"]["cpu"])
    threads = int(flags["workers"]) * int(flags["threads_per_job"])
    if threads > cpu_limit:
        problem(f"workers x threads_per_job = {threads} threads exceed the CPU limit {cpu_limit}")
    for r in ("cpu", "memory"):
        conv = quantity_cpu if r == "cpu" else quantity_bytes
        if conv(res["requests"][r]) > conv(res["limits"][r]):
            problem(f"{r} request above its limit")
    # Memory: the admitted jobs' estimates (server/memory_budget.h) are bounded by the budget;
    # the idle server and its buffers need ~128 MiB beside it. A largest job must fit alone.
    if "memory_budget_mib" not in flags:
        problem("the ConfigMap does not set --memory_budget_mib (the default reads the node's memory)")
        return None
    budget = int(flags["memory_budget_mib"]) * 2**20
    if budget + 128 * 2**20 > quantity_bytes(res["limits"]["memory"]):
        problem(f"--memory_budget_mib={flags['memory_budget_mib']} leaves under 128 MiB of the memory limit")
    header = open(os.path.join(DEPLOY, "..", "server", "memory_budget.h")).read()
    factor = {k: int(re.search(rf"{k} = (\d+);", header).group(1))
              for k in ("kBytesPerVertex", "kBytesPerFace")}
    base = int(re.search(r"kJobBaseBytes = uint64_t\{(\d+)\} << 20;", header).group(1)) * 2**20
    largest = base + factor["kBytesPerVertex"] * int(flags.get("max_vertices", 20_000_000)) + \
        factor["kBytesPerFace"] * int(flags["max_faces"])
    if largest > budget:
        problem(f"a largest job (--max_faces, --max_vertices) needs ~{largest >> 20} MiB, above the budget")
    grace = float(flags["grace_period_seconds"])
    pre_stop = 5
    if pod["spec"]["terminationGracePeriodSeconds"] < grace + pre_stop + 5:
        problem("terminationGracePeriodSeconds leaves running jobs less than --grace_period_seconds")
    sec = pod["spec"].get("securityContext", {})
    if not sec.get("runAsNonRoot"):
        problem("the pod may run as root")
    if sec.get("fsGroup") != sec.get("runAsGroup"):
        problem("fsGroup is not the server's group: it cannot read the 0440 Secret files")

    hpa = by_kind["HorizontalPodAutoscaler"][0]
    ref = hpa["spec"]["scaleTargetRef"]
    if (ref["kind"], ref["name"]) != ("Deployment", dep["metadata"]["name"]):
        problem("the HPA does not scale the Deployment")
    if hpa["spec"]["minReplicas"] > hpa["spec"]["maxReplicas"] or hpa["spec"]["minReplicas"] < 2:
        problem("the HPA's replica range leaves no redundancy")
    if pdb["spec"].get("maxUnavailable", 0) >= hpa["spec"]["minReplicas"]:
        problem("the PDB lets every replica go at once")
    if not problems:
        ok("selectors, ports, TLS probes, scrape annotations, flagfile, Secrets, resources, "
           "HPA, PDB, NetworkPolicy agree")
    return flags, container, sec


def check_tls_flags(flags, where):
    """A listener beyond loopback only with TLS, never --plaintext_remote, and tenants on."""
    if "plaintext_remote" in flags:
        problem(f"{where} passes --plaintext_remote")
    missing = [f for f in TLS_FLAGS if not flags.get(f)]
    if missing:
        problem(f"{where} does not set --{', --'.join(missing)}")


def check_no_plaintext_anywhere():
    files = [os.path.join(DEPLOY, f) for f in ("compose.yaml", "Dockerfile")]
    for d in ("k8s", "nginx", "prometheus"):
        files += [os.path.join(DEPLOY, d, f) for f in sorted(os.listdir(os.path.join(DEPLOY, d)))]
    for path in files:
        if "plaintext_remote" in open(path).read():
            problem(f"{os.path.relpath(path, DEPLOY)} mentions --plaintext_remote")


def check_compose(k8s_flags):
    path = os.path.join(DEPLOY, "compose.yaml")
    compose = yaml.safe_load(open(path))
    cmd = compose["services"]["femsimp"]["command"]
    flags = parse_flags(cmd)
    differ = {k for k in set(flags) | set(k8s_flags) if flags.get(k) != k8s_flags.get(k)}
    differ -= {"max_connection_age_seconds"}  # behind nginx, clients do not resolve replicas
    differ -= set(TLS_FLAGS)  # compose mounts its secrets in /run/secrets
    if differ:
        problem(f"compose and the ConfigMap size the replicas differently: {sorted(differ)}")
    check_tls_flags(flags, "compose's femsimp")
    declared = compose.get("secrets", {})
    targets = {}
    for name, svc in compose["services"].items():
        for sref in svc.get("secrets", []):
            if sref["source"] not in declared:
                problem(f"compose service {name} uses the undeclared secret {sref['source']}")
            targets.setdefault(name, set()).add("/run/secrets/" + sref.get("target", sref["source"]))
    for f in TLS_FLAGS:
        if flags.get(f) and flags[f] not in targets.get("femsimp", set()):
            problem(f"compose's --{f}={flags[f]} is not one of femsimp's secrets")
    if "/run/secrets/ca.pem" not in targets.get("femsimp", set()):
        problem("compose's femsimp lacks the CA its HEALTHCHECK trusts (/run/secrets/ca.pem)")
    nginx_files = set(re.findall(r"(/run/secrets/\S+);", open(os.path.join(DEPLOY, "nginx", "nginx.conf")).read()))
    if not nginx_files or not nginx_files <= targets.get("lb", set()):
        problem(f"nginx.conf reads {sorted(nginx_files)}, compose's lb mounts {sorted(targets.get('lb', []))}")
    for name, svc in compose["services"].items():
        for p in svc.get("ports", []):
            if not str(p).startswith("127.0.0.1:"):
                problem(f"compose service {name} publishes {p} beyond 127.0.0.1")
    tool = shutil.which("docker-compose")
    if tool:
        out = subprocess.run([tool, "-p", "femsimp", "-f", path, "config", "-q"],
                             capture_output=True, text=True)
        if out.returncode != 0:
            problem(f"docker-compose config: {out.stderr.strip()}")
        else:
            ok("docker-compose accepts deploy/compose.yaml")
    else:
        print("note: docker-compose not installed, compose.yaml checked by this script only")


def check_prometheus():
    tool = shutil.which("promtool")
    if not tool:
        print("note: promtool not installed (Debian: prometheus), Prometheus config not checked")
        return
    out = subprocess.run([tool, "check", "config", os.path.join(DEPLOY, "prometheus", "prometheus.yml")],
                         capture_output=True, text=True)
    if out.returncode != 0:
        problem(f"promtool check config: {out.stdout}{out.stderr}")
    else:
        ok("promtool accepts the Prometheus config and rules")


def check_nginx(dev_dir):
    nginx = shutil.which("nginx") or "/usr/sbin/nginx"
    if not os.path.exists(nginx):
        print("note: nginx not installed, nginx.conf not checked")
        return
    with tempfile.TemporaryDirectory() as tmp:
        conf = open(os.path.join(DEPLOY, "nginx", "nginx.conf")).read()
        # The compose network's name is not resolvable here; the rest is checked as it is.
        conf = conf.replace("/tmp/", tmp + "/")
        conf = conf.replace("server femsimp:50051", "server 127.0.0.1:1")
        conf = conf.replace("/etc/nginx/grpc-proxy.conf", os.path.join(DEPLOY, "nginx", "grpc-proxy.conf"))
        conf = conf.replace("/run/secrets/", dev_dir + "/")
        proxy = open(os.path.join(DEPLOY, "nginx", "grpc-proxy.conf")).read()
        if not re.search(r"^\s*listen [^;]*\bssl\b", conf, re.M):
            problem("nginx.conf listens without TLS")
        if "grpc_pass grpcs://" not in proxy or not re.search(r"grpc_ssl_verify on;", proxy):
            problem("grpc-proxy.conf does not pass to the replicas over verified TLS")
        with open(os.path.join(tmp, "nginx.conf"), "w") as f:
            f.write(conf)
        out = subprocess.run([nginx, "-t", "-p", tmp, "-c", os.path.join(tmp, "nginx.conf")],
                             capture_output=True, text=True)
        if out.returncode != 0:
            problem(f"nginx -t: {out.stderr.strip()}")
        else:
            ok("nginx -t accepts deploy/nginx/nginx.conf")


def check_dockerfile(container, pod_security):
    text = open(os.path.join(DEPLOY, "Dockerfile")).read()
    m = re.search(r"^USER (\d+):(\d+)", text, re.M)
    if not m or int(m.group(1)) != pod_security.get("runAsUser"):
        problem("the Dockerfile's USER is not the Deployment's runAsUser")
    exposed = set(int(p) for p in re.search(r"^EXPOSE (.*)$", text, re.M).group(1).split())
    ports = {p["containerPort"] for p in container["ports"]}
    if exposed != ports:
        problem(f"the Dockerfile exposes {sorted(exposed)}, the Deployment uses {sorted(ports)}")
    # The image builds with tests, benchmarks and fuzzing off: every other directory the
    # top-level CMakeLists.txt adds must be in the build stage.
    top = open(os.path.join(DEPLOY, "..", "CMakeLists.txt")).read()
    needed = set(re.findall(r"^\s*add_subdirectory\((\w+)\)", top, re.M)) - {"tests", "bench", "fuzz"}
    copied = set(re.findall(r"^COPY (\w+) \1$", text, re.M))
    if needed - copied:
        problem(f"the Dockerfile's build stage lacks {sorted(needed - copied)} (add_subdirectory in CMakeLists.txt)")
    cmd = re.search(r"^CMD \[(.*?)\]$", text, re.M | re.S)
    cmd_flags = parse_flags(re.findall(r'"([^"]+)"', cmd.group(1))) if cmd else {}
    check_tls_flags(cmd_flags, "the Dockerfile's CMD")
    if not re.search(r"^HEALTHCHECK[^\n]*(\\\n[^\n]*)*--tls-ca-file", text, re.M):
        problem("the Dockerfile's HEALTHCHECK does not use TLS")
    if not problems:
        ok("Dockerfile user, ports, TLS command and HEALTHCHECK match the Deployment")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--server-bin", required=True)
    parser.add_argument("--client-bin", required=True)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        dev_dir, dev_secrets = make_dev_secrets(tmp)
        objects = rendered_objects()
        result = check_k8s(objects, args, dev_secrets, tmp) if objects and dev_dir else None
        if result:
            flags, container, sec = result
            check_compose(flags)
            check_dockerfile(container, sec)
        check_no_plaintext_anywhere()
        check_prometheus()
        if dev_dir:
            check_nginx(dev_dir)
    if problems:
        print(f"check-deploy: {len(problems)} problems", file=sys.stderr)
        return 1
    print("check-deploy: PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
