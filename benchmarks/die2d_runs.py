"""What the die2d benchmarks share: run a deck and read its cycles, print a
table of the ram force against dofs and cumulative wall time, and find where
a sequence first reaches an error level."""
import json, os, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.path.join(ROOT, "build", "dieflow")
# N1: the goal-oriented sequence from the ungraded start to 1.5M dofs
# (doc/benchmarks.md, "Two estimates..."): 2468.78 +- 0.05 N/mm; it was
# 2468.6 +- 0.6 (the 2.6M-dof degree-1 Kelly run) for the tables measured
# before 2026-11-24, which say so.
CONVERGED = {"N1": 2468.78, "P1": 82.66}
MATERIAL = {
    "N1": "  set Law = Newtonian\n  set Viscosity = 0.278\n",
    "P1": "  set Law = Norton-Hoff\n  set Consistency K = 0.834\n  set Rate sensitivity m = 0.2\n",
}


def run_summary(make_deck, settings, timeout=None):
    """Runs make_deck(output=..., **settings) in a scratch folder; returns its
    summary.json (also when the run did not converge: exit status 2)."""
    with tempfile.TemporaryDirectory() as work:
        path = os.path.join(work, "deck.prm")
        with open(path, "w") as f:
            f.write(make_deck(output=os.path.join(work, "out"), **settings))
        status = subprocess.run([PROGRAM, path], stdout=subprocess.DEVNULL, timeout=timeout).returncode
        if status not in (0, 2):
            raise SystemExit(f"dieflow failed on {settings} (exit status {status})")
        with open(os.path.join(work, "out", "summary.json")) as f:
            return json.load(f)


def run(make_deck, settings):
    """Runs make_deck(output=..., **settings); returns the converged cycles
    (dofs, cumulative time, Newton its, F_x[1], its estimate) and the
    summary's extrapolation of F_x[1] (or None)."""
    summary = run_summary(make_deck, settings)
    rows, elapsed = [], 0.0
    for c in summary["cycles"]:
        if not c["converged"]:
            print(f"\n(cycle {c['cycle']} of {settings} did not converge: the sequence stops there)")
            break
        elapsed += c["wall_time"]
        rows.append(dict(dofs=c["dofs"], time=elapsed, its=c["nonlinear_iterations"],
                         value=c["quantities"]["F_x[1]"],
                         estimate=c["estimated_errors"].get("F_x[1]")))
    return rows, summary.get("extrapolated", {}).get("F_x[1]")


def table(title, rows, converged, digits=2):
    print(f"\n### {title}\n")
    print("| dofs | wall time (cumulative) [s] | F_x[1] [N/mm] | error | estimated error | Newton its |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        estimate = "-" if r["estimate"] is None else f"{100 * r['estimate'] / abs(r['value']):.3f}%"
        print(f"| {r['dofs']} | {r['time']:.2f} | {r['value']:.{digits}f} | "
              f"{100 * (r['value'] / converged - 1):+.{digits + 1}f}% | {estimate} | {r['its']} |")


def reach_table(title, summary, levels):
    """The table of dofs / cumulative wall time each sequence needs to reach
    each error level: summary holds (sequence title, cells per level)."""
    print(f"\n### {title}: dofs / cumulative wall time to reach the error\n")
    print("| sequence | " + " | ".join(f"{100 * level:g} %" for level in levels) + " |")
    print("|---|" + "---|" * len(levels))
    for sequence, cells in summary:
        print(f"| {sequence} | " + " | ".join(cells) + " |")


def reached(rows, converged, level):
    for r in rows:
        if abs(r["value"] / converged - 1) <= level:
            return f"{r['dofs']} / {r['time']:.2f} s"
    return "not reached"
