#!/usr/bin/env python3
"""The service's cost over the engine (docs/BENCHMARKS.md, "The service at engine speed").

For each option set, side by side in one run and interleaved (local, server, local, ...):
  engine    the engine alone, the mesh loaded (`engine_seconds` of the local run's --stats-json)
  local     `femsimp simplify IN OUT` file in -> file out (wall, and its peak RSS: the engine's
            peak memory for the job)
  server    `femsimp simplify IN OUT --server` through a femsimp-server on loopback (the client's
            wall), a fresh server per repetition (--workers 1), its peak RSS (VmHWM) and its
            per-stage histograms (femsimp_stage_duration_seconds) scraped after the job.
Best of REPS for each figure. On a shared, loaded machine the engine's time varies more than
the service adds, so the script also reports what each path adds around the engine: its wall
minus that same run's engine seconds (the remote run's from the Result).

  bench/service_overhead.py [--mesh M] [--reps N] [--threads T]
Default mesh: bench/data/blade_loop3.ply
(build/bench/make_meshes tests/data/blade.off bench/data/blade_loop 3 4).
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

OPTION_SETS = [
    ("paper, --min-angle 0 --ratio 0.1", ["--preset", "paper", "--min-angle", "0", "--ratio", "0.1"]),
    ("defaults (fe preset)", []),
]
STAGES = ["upload", "repair", "build", "engine", "encode", "download"]


def timed(cmd, out_dir):
    """Runs cmd under /usr/bin/time; returns (wall seconds, peak RSS KiB)."""
    tfile = os.path.join(out_dir, "time")
    subprocess.run(["/usr/bin/time", "-f", "%e %M", "-o", tfile] + cmd, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall, rss = open(tfile).read().split()[-2:]
    return float(wall), int(rss)


def start_server(build, threads, log_path):
    log = open(log_path, "w")
    proc = subprocess.Popen([f"{build}/server/femsimp-server", "--listen=127.0.0.1:0",
                             "--metrics_listen=127.0.0.1:0", "--workers=1",
                             f"--threads_per_job={threads}"], stdout=log, stderr=log)
    for _ in range(200):
        m = re.search(r"listening on \S+ \(port (\d+)\).*?\(port (\d+)\)", open(log_path).read())
        if m:
            return proc, int(m.group(1)), int(m.group(2))
        time.sleep(0.05)
    proc.kill()
    sys.exit(f"femsimp-server did not start: {open(log_path).read()}")


def peak_rss_kib(pid):
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1])
    return 0


def stage_seconds(metrics_port):
    text = urllib.request.urlopen(f"http://127.0.0.1:{metrics_port}/metrics", timeout=5).read()
    stages = {}
    for line in text.decode().splitlines():
        m = re.match(r'femsimp_stage_duration_seconds_sum\{(.*)\} (\S+)', line)
        if m:
            stage = re.search(r'stage="(\w+)"', m.group(1)).group(1)
            stages[stage] = float(m.group(2))
    return stages


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mesh", default="bench/data/blade_loop3.ply")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--build", default="build")
    args = ap.parse_args()
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    cli = f"{args.build}/client/femsimp"
    work = tempfile.mkdtemp(prefix="femsimp-service-overhead.")
    ext = os.path.splitext(args.mesh)[1]
    rows = []
    try:
        for name, flags in OPTION_SETS:
            best = {}

            def keep(key, value):
                best[key] = min(best.get(key, value), value)

            for rep in range(args.reps):
                stats = os.path.join(work, "stats.json")
                wall, rss = timed([cli, "simplify", args.mesh, os.path.join(work, "local" + ext),
                                   "--quiet", "--threads", str(args.threads), "--stats-json",
                                   stats] + flags, work)
                engine = json.load(open(stats))["engine_seconds"]
                keep("engine", engine)
                keep("local", wall)
                keep("local_around", wall - engine)
                keep("local_rss", rss)
                proc, port, metrics_port = start_server(args.build, args.threads,
                                                        os.path.join(work, "server.log"))
                try:
                    wall, _ = timed([cli, "simplify", args.mesh, os.path.join(work, "remote" + ext),
                                     "--quiet", "--threads", str(args.threads), "--stats-json",
                                     stats, "--server", f"127.0.0.1:{port}"] + flags, work)
                    keep("server", wall)
                    keep("server_engine", json.load(open(stats))["engine_seconds"])
                    keep("server_around", wall - json.load(open(stats))["engine_seconds"])
                    keep("server_rss", peak_rss_kib(proc.pid))
                    for stage, seconds in stage_seconds(metrics_port).items():
                        keep("stage_" + stage, seconds)
                finally:
                    proc.terminate()
                    proc.wait()
                print(f"{name} rep {rep + 1}: engine {engine:.3f} s, local {best['local']:.3f} s "
                      f"(best so far), server {wall:.3f} s", file=sys.stderr)
            rows.append((name, best))
    finally:
        shutil.rmtree(work)

    print(f"mesh {args.mesh}, {args.threads} threads, best of {args.reps} interleaved repetitions")
    print()
    print("| options | engine s | local file->file s | server s | local / engine | "
          "server / local | local peak RSS MiB | server peak RSS MiB | server / local RSS |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, b in rows:
        print(f"| {name} | {b['engine']:.3f} | {b['local']:.3f} | {b['server']:.3f} | "
              f"{b['local'] / b['engine']:.2f} | {b['server'] / b['local']:.2f} | "
              f"{b['local_rss'] / 1024:.1f} | {b['server_rss'] / 1024:.1f} | "
              f"{b['server_rss'] / b['local_rss']:.2f} |")
    print()
    print("What each path adds around the engine (wall minus that run's own engine seconds, "
          "best of the repetitions), and the ratio it gives at the best engine time: "
          "(engine + server around) / (engine + local around):")
    print()
    print("| options | server's engine s | local around s | server around s | "
          "server / local at equal engine time |")
    print("|---|---:|---:|---:|---:|")
    for name, b in rows:
        e = b["engine"]
        print(f"| {name} | {b['server_engine']:.3f} | {b['local_around']:.3f} | "
              f"{b['server_around']:.3f} | {(e + b['server_around']) / (e + b['local_around']):.2f} |")
    print()
    print("Server stages (femsimp_stage_duration_seconds, best of the repetitions, s):")
    print()
    print("| options | " + " | ".join(STAGES) + " |")
    print("|---|" + "---:|" * len(STAGES))
    for name, b in rows:
        print(f"| {name} | " + " | ".join(f"{b.get('stage_' + s, float('nan')):.3f}" for s in STAGES) + " |")


if __name__ == "__main__":
    main()
