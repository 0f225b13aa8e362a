"""What the soak and probe scripts read of a running femsimp-server: its process figures from
/proc and its femsimp_ metrics from /metrics."""
import os
import re
import urllib.request


def proc_figures(pid):
    """Threads, open file descriptors, resident and peak resident memory (KiB) of a process."""
    status = {}
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            key, _, value = line.partition(":")
            status[key] = value.strip()
    return {
        "threads": int(status["Threads"]),
        "fds": len(os.listdir(f"/proc/{pid}/fd")),
        "rss_kib": int(status["VmRSS"].split()[0]),
        "hwm_kib": int(status["VmHWM"].split()[0]),
    }


def scrape_metrics(port):
    """The femsimp_ samples of http://127.0.0.1:PORT/metrics: 'name{labels}' -> value."""
    with urllib.request.urlopen(f"http://127.0.0.1:{port}/metrics", timeout=10) as r:
        text = r.read().decode()
    values = {}
    for line in text.splitlines():
        m = re.match(r"^(femsimp_\w+)(\{[^}]*\})? (\S+)$", line)
        if m:
            values[m.group(1) + (m.group(2) or "")] = float(m.group(3))
    return values
