#!/usr/bin/python3
"""Tables and plot data of the cell speedup study (bench/cell_study.sh). Stdlib only.

Reads DIR/<mesh>_<geo|topo|free>_cell_s<N>.json, <mesh>_<geo|topo|free>_native_t1.json and
<mesh>_geo_cell_s8_c64_k<K>.json (femsimp --stats-json files), prints markdown tables on stdout and
writes DIR/modeled.dat and DIR/measured.dat (speedup per SPE count, one column per series) for
bench/cell_study.gp.

Every figure is labelled: "modeled" = the cellsim cycle model (3.2 GHz for seconds), "measured" =
host wall clock (engine_seconds) on this machine, whose few cores run all emulated SPEs.
"""
import argparse
import json
import math
import os

CLOCK_HZ = 3.2e9
SPE_RUN_OVERHEAD = 30000  # cellsim CostModel::spe_run_overhead_cycles
CRITS = [("geo", "default criteria"), ("topo", "topology only"),
         ("free", "default criteria, --schedule free")]
# Paper, Table 1 (one SPE on an IBM QS21): blade (882,954 vertices) and fandisk.
PAPER = {"blade3": {"geo": 53.7, "topo": 9.0}, "fandisk": {"geo": 0.37, "topo": 0.05}}


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except FileNotFoundError:
        return None


def summary(d):
    """Totals over passes of one run."""
    p1 = d["passes"][0].get("modeled_pass_cycles", 0) if d["passes"] else 0
    hits = misses = stale = stale_reread = stale_skipped = switches = ppe = rounds = starts = 0
    slowest = mean = 0.0
    for p in d["passes"]:
        c = p.get("cell") or {}
        hits += c.get("cache_hits", 0)
        misses += c.get("cache_misses", 0)
        stale += c.get("stale_detected", 0)
        stale_reread += c.get("stale_reread", 0)
        stale_skipped += c.get("stale_skipped", 0)
        switches += c.get("thread_switches", 0)
        ppe += p.get("ppe_cycles", 0)
        rounds += p.get("rounds", 0)
        # The removal's SPE runs' starts and ends (files from before the field: deterministic
        # rounds launched and joined the SPEs twice a round, for the fan boxes and removals).
        starts += p.get("spe_start_cycles", 2 * p.get("rounds", 0) * SPE_RUN_OVERHEAD)
        per = [s["modeled_cycles"] for s in p.get("cell_per_spe", [])]
        if per:
            slowest += max(per)
            mean += sum(per) / len(per)
    return {
        "cycles": d.get("modeled_cycles", 0),
        "p1": p1,
        "wall": d["engine_seconds"],
        "out_v": d["output"]["vertices"],
        "in_v": d["input"]["vertices"],
        "passes": len(d["passes"]),
        "hit": hits / (hits + misses) if hits + misses else float("nan"),
        "stale": stale,
        "stale_reread": stale_reread,
        "stale_skipped": stale_skipped,
        "switches": switches,
        "ppe": ppe,
        "round_runs": starts,
        "imbalance": slowest / mean if mean else float("nan"),
    }


def fmt_int(x):
    return f"{x:,}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dir", required=True)
    ap.add_argument("--spes", default="1 2 4 8 16 32 64 128")
    ap.add_argument("--meshes", default="fandisk blade3")
    a = ap.parse_args()
    spes = [int(s) for s in a.spes.split()]
    meshes = a.meshes.split()
    runs = {}
    for m in meshes:
        for c, _ in CRITS:
            for n in spes:
                d = load(os.path.join(a.dir, f"{m}_{c}_cell_s{n}.json"))
                if d:
                    runs[(m, c, n)] = summary(d)
            d = load(os.path.join(a.dir, f"{m}_{c}_native_t1.json"))
            if d:
                runs[(m, c, "native")] = summary(d)
        for c, _ in CRITS:
            for k in (1, 2):
                d = load(os.path.join(a.dir, f"{m}_{c}_cell_s8_c64_k{k}.json"))
                if d:
                    runs[(m, c, "k", k)] = summary(d)

    out = []
    w = out.append
    series = [(m, c, f"{m} {cname}") for m in meshes for c, cname in CRITS
              if (m, c, spes[0]) in runs]
    # Fixed column order of the plot data (bench/cell_study.gp).
    plot_series = [(m, c, f"{m} {dict(CRITS)[c]}") for m, c in
                   (("fandisk", "geo"), ("fandisk", "topo"), ("blade3", "geo"), ("blade3", "topo"),
                    ("blade3", "free"))]

    w("### Speedup per SPE count (cell back end, default 64 KiB cache, 1 software thread)\n")
    w("Modeled = cellsim cycle model (seconds at 3.2 GHz); measured = host wall clock "
      "(`engine_seconds`) on this machine's 2 cores, which run all N emulated SPEs, so the measured "
      "speedup cannot exceed ~2.\n")
    for m, c, title in series:
        base = runs.get((m, c, spes[0]))
        if not base:
            continue
        w(f"\n**{title}** ({fmt_int(base['in_v'])} input vertices)\n")
        w("| SPEs | modeled cycles | modeled s | modeled speedup | modeled speedup, pass 1 only | modeled PPE share "
          "| modeled SPE start/stop share | modeled slowest/mean SPE | measured wall s | measured speedup (2 host cores) "
          "| output vertices | passes | hit ratio | stale detected (re-read / skipped) |")
        w("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
        for n in spes:
            r = runs.get((m, c, n))
            if not r:
                continue
            w(f"| {n} | {fmt_int(r['cycles'])} | {r['cycles'] / CLOCK_HZ:.4f} "
              f"| {base['cycles'] / r['cycles']:.2f} | {base['p1'] / r['p1']:.2f} | {100 * r['ppe'] / r['cycles']:.1f} % "
              f"| {100 * r['round_runs'] / r['cycles']:.1f} % "
              f"| {r['imbalance']:.2f} | {r['wall']:.3f} | {base['wall'] / r['wall']:.2f} "
              f"| {fmt_int(r['out_v'])} | {r['passes']} | {100 * r['hit']:.1f} % "
              f"| {r['stale']} ({r['stale_reread']} / {r['stale_skipped']}) |")

    w("\n(pass 1 only: every run's first pass tries the same candidates on the same input mesh, so "
      "its modeled speedup is free of the pass-count differences between runs.)\n")
    w("\n### One SPE vs the paper's Table 1\n")
    w("| model | input vertices | criteria | modeled s, 1 SPE (3.2 GHz) | measured wall s, cell 1 SPE "
      "| measured wall s, native 1 thread | cell / native (measured) | paper Table 1, 1 SPE on QS21 |")
    w("| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: |")
    for m, c, title in series:
        r, nat = runs.get((m, c, 1)), runs.get((m, c, "native"))
        if not r:
            continue
        nat_s = f"{nat['wall']:.3f}" if nat else "-"
        ratio = f"{r['wall'] / nat['wall']:.2f}x" if nat else "-"
        paper = PAPER.get(m, {}).get(c)
        paper_s = f"{paper} s" + (" (blade: 882,954 vertices)" if m == "blade3" else "") if paper else "-"
        cname = dict(CRITS)[c]
        w(f"| {m} | {fmt_int(r['in_v'])} | {cname} | {r['cycles'] / CLOCK_HZ:.3f} | {r['wall']:.3f} "
          f"| {nat_s} | {ratio} | {paper_s} |")

    w("\n### Software threads (8 SPEs, 64 KiB cache)\n")
    w("| model | criteria | --spe-threads | modeled cycles | modeled gain vs 1 thread "
      "| modeled gain, pass 1 only | passes | thread switches | hit ratio | output vertices "
      "| measured wall s |")
    w("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for m in meshes:
      for c, cname in CRITS:
        one = runs.get((m, c, "k", 1))
        for k in (1, 2):
            r = runs.get((m, c, "k", k))
            if not r:
                continue
            gain = f"{100 * (one['cycles'] / r['cycles'] - 1):+.1f} %" if one else "-"
            g1 = f"{100 * (one['p1'] / r['p1'] - 1):+.1f} %" if one else "-"
            w(f"| {m} | {cname} | {k} | {fmt_int(r['cycles'])} | {gain} | {g1} | {r['passes']} | {fmt_int(r['switches'])} "
              f"| {100 * r['hit']:.1f} % | {fmt_int(r['out_v'])} | {r['wall']:.3f} |")
    print("\n".join(out))

    # Plot data: N, ideal, then one column per series (NaN where missing).
    # The modeled data also has the pass-1-only speedup of the two blade3 geometric series.
    pass1 = [("blade3", "geo", "blade3 default criteria, pass 1"),
             ("blade3", "free", "blade3 default criteria --schedule free, pass 1")]
    for kind, key in (("modeled", "cycles"), ("measured", "wall")):
        with open(os.path.join(a.dir, f"{kind}.dat"), "w") as f:
            f.write("# SPEs ideal " + " ".join(f'"{t}"' for _, _, t in plot_series + pass1) + "\n")
            for n in spes:
                cols = [str(n), str(n)]
                for m, c, _ in plot_series:
                    b, r = runs.get((m, c, spes[0])), runs.get((m, c, n))
                    cols.append(f"{b[key] / r[key]:.4f}" if b and r else "NaN")
                for m, c, _ in pass1:
                    b, r = runs.get((m, c, spes[0])), runs.get((m, c, n))
                    ok = kind == "modeled" and b and r
                    cols.append(f"{b['p1'] / r['p1']:.4f}" if ok else "NaN")
                f.write(" ".join(cols) + "\n")


if __name__ == "__main__":
    main()
