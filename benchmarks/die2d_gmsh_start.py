#!/usr/bin/env python3
"""A user's Gmsh mesh as the start: die2d meshed by Gmsh with cells of h/32
at the die corners C and D (benchmarks/die2d-graded.geo, the mesh the
accuracy issue measured with; h = 2), velocity degree 2, the default deck
otherwise, Kelly (fraction 0.5) against the goal-oriented indicator (fixed
fraction 0.9). Errors of the ram force against the converged 2468.78 N/mm
(benchmarks/die2d_runs.py). Needs the gmsh program (apt install gmsh).

    python3 benchmarks/die2d_gmsh_start.py

Not a test: the times are this machine's (run one benchmark at a time).
"""
import os
import shutil
import subprocess
import tempfile

from die2d_runs import CONVERGED, ROOT, reach_table, reached, run as run_deck, table

LEVELS = (0.01, 0.001, 0.0005, 0.0001)
GEO = os.path.join(ROOT, "benchmarks", "die2d-graded.geo")


def deck(output, mesh, indicator, marking, fraction, cycles):
    text = open(os.path.join(ROOT, "parameters", "die2d-held-land.prm")).read()
    start = text.index("subsection Mesh")
    end = text.index("\nend\n", start) + len("\nend\n")
    text = text[:start] + f"subsection Mesh\n  set Source = gmsh\n  set Gmsh file = {mesh}\nend\n" + text[end:]
    for key, value in (("set Output directory", f"set Output directory = {output}"),
                       ("set Write VTU", "set Write VTU = false"),
                       ("  set Cycles", f"  set Cycles = {cycles}"),
                       ("  set Indicator", f"  set Indicator = {indicator}\n  set Marking = {marking}"),
                       ("  set Refine fraction", f"  set Refine fraction = {fraction}")):
        line = text.index(key)
        text = text[:line] + value + text[text.index("\n", line):]
    return text


def main():
    if shutil.which("gmsh") is None:
        raise SystemExit("this benchmark needs gmsh: apt install gmsh")
    converged = CONVERGED["N1"]
    with tempfile.TemporaryDirectory() as work:
        mesh = os.path.join(work, "die2d-graded.msh")
        subprocess.run(["gmsh", "-2", "-format", "msh22", "-setnumber", "h", "2", GEO, "-o", mesh],
                       stdout=subprocess.DEVNULL, check=True)
        summary = []
        for title, settings in (
                ("Gmsh start (h = 2, h/32 at C and D), degree 2, Kelly fraction 0.5",
                 dict(indicator="kelly", marking="fixed fraction", fraction=0.5, cycles=13)),
                ("Gmsh start (h = 2, h/32 at C and D), degree 2, dual-weighted indicator, fixed fraction 0.9",
                 dict(indicator="dual weighted", marking="fixed fraction", fraction=0.9, cycles=13))):
            rows, _ = run_deck(lambda **kw: deck(mesh=mesh, **kw), settings)
            table(f"N1, {title}", rows, converged, digits=3)
            summary.append((title, [reached(rows, converged, level) for level in LEVELS]))
    reach_table("N1 from the Gmsh start", summary, LEVELS)


if __name__ == "__main__":
    main()
