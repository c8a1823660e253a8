#!/usr/bin/env python3
"""Work-precision on an exact case: the plane Stokes sink flow of
tests/sink_flow.prm (the inlet meets an inclined frictionless die; inlet
force F_x[1] = -0.4 exactly). Degree 1 against degree 2, uniform against
adaptive refinement (Kelly, and the goal-oriented dual-weighted indicator;
at most about 20,000 cells):
per sequence the dofs, cumulative wall time and error of F_x[1] per cycle,
then the dofs and time each needs for 1 %, 0.1 %, 0.01 % and 0.001 %.

    python3 benchmarks/exact_work_precision.py

Not a test: the times are this machine's (run one benchmark at a time).
"""
import json
import os
import subprocess
import tempfile

from die2d_runs import PROGRAM, ROOT

EXACT = -0.4
LEVELS = (0.01, 0.001, 0.0001, 0.00001)
MESH = os.path.join(ROOT, "tests", "meshes", "sink_trapezoid.msh")


def deck(output, degree, strategy, indicator, marking, fraction, cycles):
    return f"""set Output directory = {output}
set Write VTU = false
subsection Mesh
  set Source = gmsh
  set Gmsh file = {MESH}
  set Global refinements = 1
end
subsection Material
  set Law = Newtonian
  set Viscosity = 1
  set Penalty factor = 1e8
end
subsection Boundary conditions
  set Prescribed velocity ids = 1
  set Symmetry ids = 5
  set Slip wall ids =
  set Traction free ids =
  set Traction ids = 2
  set Traction = -2*(1/((x-2)^2+y^2) - 2*(x-2)^2/((x-2)^2+y^2)^2); 4*(x-2)*y/((x-2)^2+y^2)^2
  subsection Prescribed velocity 1
    set Velocity = -(x-2)/((x-2)^2+y^2); -y/((x-2)^2+y^2)
  end
end
subsection Contact
  set Die ids = 3
  set Friction coefficients = 3: 0
end
subsection Discretisation
  set Velocity degree = {degree}
end
subsection Refinement
  set Cycles = {cycles}
  set Strategy = {strategy}
  set Indicator = {indicator}
  set Marking = {marking}
  set Refine fraction = {fraction}
  set Maximum cells = 20000
end
"""


def run(**settings):
    with tempfile.TemporaryDirectory() as work:
        path = os.path.join(work, "deck.prm")
        with open(path, "w") as f:
            f.write(deck(os.path.join(work, "out"), **settings))
        subprocess.run([PROGRAM, path], stdout=subprocess.DEVNULL, check=True, timeout=600)
        with open(os.path.join(work, "out", "summary.json")) as f:
            summary = json.load(f)
    rows, elapsed = [], 0.0
    for c in summary["cycles"]:
        if not c["converged"]:
            break
        elapsed += c["wall_time"]
        value = c["quantities"]["F_x[1]"]
        rows.append(dict(dofs=c["dofs"], time=elapsed, value=value, error=abs(value / EXACT - 1)))
    return rows


def reached(rows, level):
    for r in rows:
        if r["error"] <= level:
            return f"{r['dofs']} / {r['time']:.2f} s"
    return "not reached"


def main():
    sequences = []
    for degree in (1, 2):
        uniform_cycles = 7 if degree == 1 else 6
        sequences += [
            (f"degree {degree}, uniform", dict(degree=degree, strategy="global", indicator="kelly",
                                             marking="fixed fraction", fraction=0.3, cycles=uniform_cycles)),
            (f"degree {degree}, Kelly, fixed fraction 0.5", dict(degree=degree, strategy="adaptive", indicator="kelly",
                                                              marking="fixed fraction", fraction=0.5, cycles=12)),
            (f"degree {degree}, dual weighted, fixed fraction 0.9",
             dict(degree=degree, strategy="adaptive", indicator="dual weighted", marking="fixed fraction",
                  fraction=0.9, cycles=12)),
        ]
    summary = []
    for title, settings in sequences:
        rows = run(**settings)
        print(f"\n### {title}\n")
        print("| dofs | wall time (cumulative) [s] | F_x[1] | relative error |")
        print("|---|---|---|---|")
        for r in rows:
            print(f"| {r['dofs']} | {r['time']:.3f} | {r['value']:.9f} | {r['error']:.2e} |")
        summary.append((title, [reached(rows, level) for level in LEVELS]))
    print("\n### Sink flow inlet force: dofs / cumulative wall time to reach the error\n")
    print("| sequence | " + " | ".join(f"{100 * level:g} %" for level in LEVELS) + " |")
    print("|---|" + "---|" * len(LEVELS))
    for title, cells in summary:
        print(f"| {title} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
