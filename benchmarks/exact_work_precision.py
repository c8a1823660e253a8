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
import os

from die2d_runs import ROOT, reach_table, reached, run_summary

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
    summary = run_summary(deck, settings, timeout=600)
    rows, elapsed = [], 0.0
    for c in summary["cycles"]:
        if not c["converged"]:
            break
        elapsed += c["wall_time"]
        value = c["quantities"]["F_x[1]"]
        rows.append(dict(dofs=c["dofs"], time=elapsed, value=value, error=abs(value / EXACT - 1)))
    return rows


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
        summary.append((title, [reached(rows, EXACT, level) for level in LEVELS]))
    reach_table("Sink flow inlet force", summary, LEVELS)


if __name__ == "__main__":
    main()
