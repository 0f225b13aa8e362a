#!/usr/bin/python3
"""Summary of the fidelity table (bench/fidelity_table.sh, docs/FIDELITY.md).

Reads the markdown table fidelity_table prints (a file, or stdin) and prints one row per mesh and
tolerance: the vertices each tool kept, marked when its output is outside the tolerance (✘ and
its distance), intersects itself (s-i) or timed out; then femsimp's fewest vertices within the
bound against CGAL's envelope run, if that one finished within the bound without intersecting
itself, and the CPU time of each of those two runs; and the fastest femsimp run that is valid with
no more vertices than that CGAL run (issue 13's target: at least 50x faster), with its speed-up.

Usage: /usr/bin/python3 bench/fidelity_summary.py [TABLE.md]
"""

import sys

COLUMNS = ["mesh", "v_in", "tolerance", "tool", "v_out", "hausdorff", "within", "cpu"]


def rows(lines):
    for line in lines:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == len(COLUMNS) and cells[0] not in ("mesh", "---"):
            yield dict(zip(COLUMNS, cells))


def valid(run):
    """Within the bound, no self-intersection, finished."""
    return run["within"] == "yes" and not timed_out(run)


def timed_out(run):
    return run["cpu"].startswith("timed out")


def seconds(run):
    return float(run["cpu"].split()[-1])


def cell(run):
    if run["v_out"] == "error":
        return "error"
    s = run["v_out"]
    if not run["within"].startswith("yes"):
        s += f" ✘ {run['hausdorff']}"
    if "self-int." in run["within"]:
        s += " s-i"
    if timed_out(run):
        s += " (timed out)"
    return s


def main():
    with open(sys.argv[1]) if len(sys.argv) > 1 else sys.stdin as f:
        runs = list(rows(f))
    tools, configs = [], {}
    for r in runs:
        if r["tool"] not in tools:
            tools.append(r["tool"])
        configs.setdefault((r["mesh"], r["v_in"], r["tolerance"]), {})[r["tool"]] = r
    print("| mesh | V in | tolerance | " + " | ".join(tools)
          + " | fewest femsimp valid | its CPU s | CGAL CPU s | V femsimp / CGAL "
          "| CPU CGAL / femsimp | fastest femsimp valid with at most CGAL's V "
          "| CPU CGAL / that |")
    print("|---|---:|---:|" + "---:|" * len(tools) + "---|---:|---:|---:|---:|---|---:|")
    for (mesh, v_in, tol), by_tool in configs.items():
        cells = [cell(by_tool[t]) if t in by_tool else "-" for t in tools]
        ok = [r for t, r in by_tool.items() if t.startswith("femsimp ") and valid(r)]
        best = min(ok, key=lambda r: int(r["v_out"])) if ok else None
        cgal = by_tool.get("CGAL envelope")
        best_text = f"{best['v_out']} ({best['tool'][len('femsimp '):]})" if best else "none"
        best_s = f"{seconds(best):.3g}" if best else "-"
        cgal_s = f"{seconds(cgal):.3g}" if cgal and cgal["v_out"] != "error" else "-"
        ratio_v = ratio_t = "-"
        fastest_text = fastest_t = "-"
        # Compared only with a CGAL run that is valid too, as issue 13 asks.
        if best and cgal and valid(cgal):
            ratio_v = f"{int(best['v_out']) / int(cgal['v_out']):.2f}"
            ratio_t = f"{seconds(cgal) / seconds(best):.0f}"
            fewer = [r for r in ok if int(r["v_out"]) <= int(cgal["v_out"])]
            fastest = min(fewer, key=seconds) if fewer else None
            fastest_text = (f"{fastest['v_out']} ({fastest['tool'][len('femsimp '):]}, "
                            f"{seconds(fastest):.3g} s)" if fastest else "none")
            if fastest:
                fastest_t = f"{seconds(cgal) / seconds(fastest):.0f}"
        print(f"| {mesh} | {v_in} | {tol} | " + " | ".join(cells)
              + f" | {best_text} | {best_s} | {cgal_s} | {ratio_v} | {ratio_t}"
              + f" | {fastest_text} | {fastest_t} |")


if __name__ == "__main__":
    main()
