#!/usr/bin/python3
"""FE check of the fidelity table's outputs (bench/fidelity_table.sh, docs/FIDELITY.md).

Reads the runs.tsv that `fidelity_table --write DIR` writes, runs `femsimp check INPUT OUTPUT
--json` (tetgen, then a free-free modal analysis in CalculiX) on each selected run and prints a
markdown table of the relative differences: volume, the worst principal moment, the worst of the
first non-rigid eigenfrequencies. A run `femsimp check` refuses (an open or self-intersecting
surface, a CalculiX failure) is listed with the reason; nothing is left out silently.

Usage: /usr/bin/python3 bench/fe_check_table.py DIR/runs.tsv [--femsimp build/client/femsimp]
         [--tolerances 0.01] [--meshes fandisk,femur] [--tools 'femsimp fe,CGAL envelope']
         [-- extra femsimp check arguments, e.g. --mesh-size 0.1]
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

# femsimp check's exit codes (femsimp check --help) that mean "this pair cannot be checked".
REFUSED = {3: "unreadable", 4: "not a closed solid, or tetgen refused it", 6: "CalculiX failed",
           9: "tetgen or ccx missing"}


def selected(row, args):
    if args.tolerances and float(row["tolerance"]) not in args.tolerances:
        return False
    if args.meshes and row["mesh"] not in args.meshes:
        return False
    return not args.tools or row["tool"] in args.tools


def check(femsimp, row, extra):
    """Runs femsimp check on one run; returns (differences dict or None, message, seconds)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "check.json")
        start = time.monotonic()
        proc = subprocess.run([femsimp, "check", row["input"], row["output"], "--json", out,
                               "--quiet"] + extra, capture_output=True, text=True)
        seconds = time.monotonic() - start
        if proc.returncode != 0:
            lines = (proc.stderr or proc.stdout).strip().splitlines()
            why = REFUSED.get(proc.returncode, f"exit {proc.returncode}")
            return None, f"{why}: {lines[-1] if lines else ''}", seconds
        with open(out) as f:
            report = json.load(f)
    return report, "", seconds


def pct(x):
    return f"{100 * x:.3g} %"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs")
    ap.add_argument("--femsimp", default="build/client/femsimp")
    ap.add_argument("--tolerances", type=lambda s: [float(t) for t in s.split(",") if t],
                    default=[], help="only these tolerances (default all)")
    ap.add_argument("--meshes", type=lambda s: [m for m in s.split(",") if m], default=[],
                    help="only these meshes (default all)")
    ap.add_argument("--tools", type=lambda s: [t for t in s.split(",") if t], default=[],
                    help="only these tools, as the table names them (default all)")
    args, extra = ap.parse_known_args()
    extra = [a for a in extra if a != "--"]
    if not os.access(args.femsimp, os.X_OK):
        sys.exit(f"fe_check_table: no femsimp CLI at {args.femsimp} (build it: ninja femsimp)")
    with open(args.runs, newline="") as f:
        rows = [r for r in csv.DictReader(f, delimiter="\t") if selected(r, args)]

    print("FE check of the outputs above (`femsimp check INPUT OUTPUT"
          + "".join(" " + a for a in extra) + "`: tetgen keeping the surface, CalculiX C3D10, "
          "steel, free-free): relative differences simplified vs. input.\n")
    print("| mesh | tolerance | tool | V out | volume | worst principal moment "
          "| worst of first 6 frequencies | tetrahedra in -> out | check s |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|")
    for row in rows:
        report, why, seconds = check(args.femsimp, row, extra)
        head = f"| {row['mesh']} | {pct(float(row['tolerance']))} | {row['tool']} | " \
               f"{row['vertices']} |"
        if report is None:
            print(f"{head} {why} | | | | {seconds:.0f} |", flush=True)
            continue
        d = report["differences"]
        tets = f"{report['original']['tetrahedra']} -> {report['simplified']['tetrahedra']}"
        print(f"{head} {pct(d['volume'])} | {pct(d['worst_moment'])} | "
              f"{pct(d['worst_frequency'])} | {tets} | {seconds:.0f} |", flush=True)


if __name__ == "__main__":
    main()
