#!/usr/bin/python3
"""Soak test of femsimp-server (issue 15): at least --jobs Simplify jobs from femsimp-load with
random cancels, client kills and one server restart, then checks that nothing is held.

One femsimp-server on a free loopback port. Work comes in rounds: each round starts --loaders
femsimp-load processes (--clients clients each, --verify: every completed output is assembled
and checked: a valid mesh with its input's topology) while a canceller cancels random queued and
running jobs (CancelJob) and, with probability --kill-probability, one of the load processes is
killed (SIGKILL) at a random moment. In the middle round the server gets SIGTERM while the load
runs and is started again on the same port (the load generators retry UNAVAILABLE). Rounds go on
until the servers have ended --jobs Simplify calls (femsimp_jobs_total, every status).

After each round, once the load is gone, the server must be idle: no job QUEUED or RUNNING
(ListJobs), queue depth and running jobs 0 (/metrics), and its threads, open file descriptors
and resident memory (/proc/PID) are sampled. At the end the last server may hold no more threads
or descriptors than at the most at any earlier idle point of its own (waiting a few seconds for
connections of killed clients to close, and gRPC's pool to shrink): something held per job or
per round would make the end the highest; its resident memory may exceed that after its first
round (the baseline) by at most --rss-slack-mib.
Every job of every load process that was not killed must have ended OK or CANCELLED (no other
status, no lost job, no invalid output). Prints the figures, a JSON summary with --json-out.

    scripts/soak.py [--build build] [--jobs 10000] [--seed 1] [--json-out FILE]

Exit 0 when every check passed, 1 otherwise.
"""
import argparse
import json
import os
import random
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(REPO, "python"))
from server_figures import proc_figures, scrape_metrics  # noqa: E402
import femsimp  # noqa: E402  (the checkout's Python client, for ListJobs and CancelJob)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]




class Server:
    def __init__(self, build, port, metrics_port, log_path):
        self.port, self.metrics_port = port, metrics_port
        self.log = open(log_path, "a")
        self.proc = subprocess.Popen(
            [os.path.join(build, "server", "femsimp-server"), f"--listen=127.0.0.1:{port}",
             f"--metrics_listen=127.0.0.1:{metrics_port}", "--workers=2", "--queue_capacity=16",
             "--threads_per_job=1", "--grace_period_seconds=5"],
            stdout=self.log, stderr=subprocess.STDOUT)
        self.client = femsimp.Client(f"127.0.0.1:{port}", max_attempts=1)
        for _ in range(300):
            try:
                self.client.server_info(timeout=1)
                return
            except femsimp.FemsimpError:
                if self.proc.poll() is not None:
                    break
                time.sleep(0.1)
        raise RuntimeError(f"femsimp-server did not come up (see {log_path})")

    def metrics(self):
        return scrape_metrics(self.metrics_port)

    def jobs_ended(self):
        return int(sum(v for k, v in self.metrics().items()
                       if k.startswith("femsimp_jobs_total{")))

    def stop(self):
        """SIGTERM: the server finishes or cancels its jobs within the grace period, exits 0."""
        t0 = time.monotonic()
        self.proc.send_signal(signal.SIGTERM)
        rc = self.proc.wait(timeout=60)
        self.client.close()
        self.log.close()
        return rc, time.monotonic() - t0


def wait_idle(server, failures, where, timeout=30):
    """Every job ended (none QUEUED or RUNNING) and no slot held, once the load is gone."""
    deadline = time.monotonic() + timeout
    while True:
        busy = [j for j in server.client.jobs(include_finished=False)
                if j.state in ("QUEUED", "RUNNING")]
        m = server.metrics()
        held = m.get("femsimp_queue_depth", 0) + m.get("femsimp_running_jobs", 0)
        if not busy and held == 0:
            return
        if time.monotonic() > deadline:
            failures.append(f"{where}: {len(busy)} jobs still QUEUED/RUNNING "
                            f"({[j.job_id for j in busy][:5]}), queue depth + running = {held}")
            return
        time.sleep(0.2)


def wait_released(pid, baseline, timeout=15):
    """The process's figures once threads and descriptors are back to the baseline (or the
    timeout passed: connections of killed clients close asynchronously)."""
    deadline = time.monotonic() + timeout
    while True:
        now = proc_figures(pid)
        if (now["threads"] <= baseline["threads"] and now["fds"] <= baseline["fds"]) or \
                time.monotonic() > deadline:
            return now
        time.sleep(0.2)


def canceller(server_ref, stop, rng, counts):
    """Cancels a random queued or running job now and then (CancelJob, as any client may)."""
    while not stop.is_set():
        stop.wait(rng.uniform(0.05, 0.3))
        try:
            live = [j for j in server_ref[0].client.jobs(include_finished=False, timeout=2)
                    if j.state in ("QUEUED", "RUNNING")]
            if live:
                counts["cancel_calls"] += 1
                if server_ref[0].client.cancel(rng.choice(live).job_id, timeout=2) in (
                        "QUEUED", "RUNNING"):
                    counts["cancelled"] += 1
        except (femsimp.FemsimpError, ValueError):
            pass  # the server is restarting (ValueError: its client was closed)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(REPO, "build"))
    ap.add_argument("--jobs", type=int, default=10000, help="Simplify calls the servers end")
    ap.add_argument("--loaders", type=int, default=4, help="femsimp-load processes per round")
    ap.add_argument("--clients", type=int, default=4, help="clients per femsimp-load")
    ap.add_argument("--jobs-per-loader", type=int, default=250)
    ap.add_argument("--kill-probability", type=float, default=0.5,
                    help="chance that a round kills one of its load processes")
    ap.add_argument("--rss-slack-mib", type=float, default=64,
                    help="resident memory the end may hold above the baseline")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--json-out")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    load_bin = os.path.join(a.build, "client", "femsimp-load")
    cli_bin = os.path.join(a.build, "client", "femsimp")
    work = tempfile.mkdtemp(prefix="femsimp-soak.")
    failures = []

    # Small meshes (a few hundred vertices each), made from the test meshes by femsimp itself.
    meshes = []
    for name, ratio in (("fandisk.off", 0.08), ("femur.off", 0.1), ("rotor_small.off", 0.15),
                        ("fandisk_groups_fields.ply", 0.08)):
        out = os.path.join(work, name.rsplit(".", 1)[0] + "-small." + name.rsplit(".", 1)[1])
        subprocess.run([cli_bin, "simplify", os.path.join(REPO, "tests", "data", name), out,
                        "--ratio", str(ratio), "--quiet", "--threads", "1"], check=True,
                       stdout=subprocess.DEVNULL)
        meshes.append(out)

    port, metrics_port = free_port(), free_port()
    log_path = os.path.join(work, "server.log")
    server_ref = [Server(a.build, port, metrics_port, log_path)]
    servers = []  # per server: pid, baseline, end figures, jobs ended
    stop_cancel = threading.Event()
    counts = {"cancel_calls": 0, "cancelled": 0}
    cancel_thread = threading.Thread(target=canceller,
                                     args=(server_ref, stop_cancel, random.Random(a.seed + 1),
                                           counts), daemon=True)
    cancel_thread.start()

    ended_before = 0  # jobs the servers stopped before the current one ended
    rounds = []
    restart = None
    peak_hwm = 0
    baseline = None
    idle_points = []  # the current server's figures at each idle point
    per_round = a.loaders * a.jobs_per_loader
    restart_round = max(1, (a.jobs // per_round) // 2)
    t_start = time.monotonic()
    r = 0
    while ended_before + server_ref[0].jobs_ended() < a.jobs:
        r += 1
        loaders = []
        for i in range(a.loaders):
            report = os.path.join(work, f"round{r}-load{i}.tsv")
            p = subprocess.Popen(
                [load_bin, "--server", f"127.0.0.1:{port}", "--clients", str(a.clients), "--jobs",
                 str(a.jobs_per_loader), "--ratio", "0.5", "--threads", "1", "--verify",
                 "--max-attempts", "30", "--jobs-report", report, "--json", *meshes],
                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            loaders.append((p, report))
        killed = None
        if rng.random() < a.kill_probability:
            killed = rng.randrange(a.loaders)
            time.sleep(rng.uniform(0.5, 8.0))
            loaders[killed][0].kill()
        if r == restart_round:
            time.sleep(rng.uniform(0.5, 3.0))
            old = server_ref[0]
            old_ended = old.jobs_ended()
            fig = proc_figures(old.proc.pid)
            peak_hwm = max(peak_hwm, fig["hwm_kib"])
            rc, seconds = old.stop()
            if rc != 0:
                failures.append(f"restart: femsimp-server exited {rc} on SIGTERM")
            servers.append({"pid": old.proc.pid, "baseline": baseline, "at_stop": fig,
                            "jobs_ended": old_ended})
            ended_before += old_ended
            server_ref[0] = Server(a.build, port, metrics_port, log_path)
            baseline = None
            idle_points = []
            restart = {"round": r, "sigterm_to_exit_seconds": round(seconds, 2), "rc": rc,
                       "jobs_ended_by_first_server": old_ended}
        round_info = {"round": r, "killed_loader": killed, "statuses": {}}
        for i, (p, report) in enumerate(loaders):
            out, err = p.communicate()
            if i == killed:
                continue
            if p.returncode not in (0, 1):  # 1: some jobs failed (cancelled ones do)
                failures.append(f"round {r} loader {i}: exit {p.returncode}: {err.strip()}")
                continue
            summary = json.loads(out)
            with open(report) as f:
                rows = [line.rstrip("\n").split("\t") for line in f][1:]
            if len(rows) != a.jobs_per_loader:
                failures.append(f"round {r} loader {i}: {len(rows)} job records, "
                                f"{a.jobs_per_loader} sent")
            if summary["duplicates"]:
                failures.append(f"round {r} loader {i}: {summary['duplicates']} duplicates")
            for row in rows:
                status = row[2]
                round_info["statuses"][status] = round_info["statuses"].get(status, 0) + 1
                if status not in ("OK", "CANCELLED"):
                    failures.append(f"round {r} loader {i} job {row[0]} ({row[1]}): {status}")
        server = server_ref[0]
        wait_idle(server, failures, f"after round {r}")
        fig = proc_figures(server.proc.pid)
        peak_hwm = max(peak_hwm, fig["hwm_kib"])
        if baseline is None:
            baseline = fig
            round_info["baseline"] = fig
        idle_points.append(fig)
        round_info["figures"] = fig
        round_info["jobs_ended_total"] = ended_before + server.jobs_ended()
        rounds.append(round_info)
        print(f"round {r}: {round_info['statuses']}, killed loader {killed}, "
              f"{round_info['jobs_ended_total']} jobs ended, server {fig}", flush=True)

    stop_cancel.set()
    cancel_thread.join()
    server = server_ref[0]
    wait_idle(server, failures, "at the end")
    most = {k: max(p[k] for p in idle_points[:-1] or idle_points) for k in ("threads", "fds")}
    end = wait_released(server.proc.pid, most)
    peak_hwm = max(peak_hwm, end["hwm_kib"])
    ended = ended_before + server.jobs_ended()
    metrics = server.metrics()
    servers.append({"pid": server.proc.pid, "baseline": baseline, "end": end,
                    "most_at_earlier_idle_points": most, "jobs_ended": server.jobs_ended()})
    if end["threads"] > most["threads"]:
        failures.append(f"threads: {end['threads']} at the end, at most {most['threads']} at the "
                        "earlier idle points")
    if end["fds"] > most["fds"]:
        failures.append(f"file descriptors: {end['fds']} at the end, at most {most['fds']} at the "
                        "earlier idle points")
    if end["rss_kib"] > baseline["rss_kib"] + a.rss_slack_mib * 1024:
        failures.append(f"resident memory: {end['rss_kib'] / 1024:.1f} MiB at the end, "
                        f"{baseline['rss_kib'] / 1024:.1f} MiB at baseline")
    rc, seconds = server.stop()
    if rc != 0:
        failures.append(f"final stop: femsimp-server exited {rc} on SIGTERM")
    statuses = {}
    for ri in rounds:
        for k, v in ri["statuses"].items():
            statuses[k] = statuses.get(k, 0) + v
    result = {
        "jobs_ended_by_servers": ended,
        "server_statuses_last": {k[len("femsimp_jobs_total"):]: int(v) for k, v in metrics.items()
                                 if k.startswith("femsimp_jobs_total{")},
        "rounds": len(rounds),
        "loaders_killed": sum(1 for ri in rounds if ri["killed_loader"] is not None),
        "statuses_of_surviving_loaders": statuses,
        "cancel_calls": counts["cancel_calls"],
        "cancelled_by_canceller": counts["cancelled"],
        "restart": restart,
        "servers": servers,
        "peak_rss_mib": round(peak_hwm / 1024, 1),
        "final_rss_mib": round(end["rss_kib"] / 1024, 1),
        "wall_seconds": round(time.monotonic() - t_start, 1),
        "failures": failures,
    }
    print(json.dumps(result, indent=1))
    if a.json_out:
        with open(a.json_out, "w") as f:
            json.dump(result, f, indent=1)
    print(f"soak: {'PASSED' if not failures else 'FAILED'}: {ended} jobs ended, "
          f"{len(failures)} failures; peak RSS {result['peak_rss_mib']} MiB, final RSS "
          f"{result['final_rss_mib']} MiB (work dir {work})")
    return 0 if not failures else 1


if __name__ == "__main__":
    sys.exit(main())
