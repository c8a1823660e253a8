#!/usr/bin/env python3
"""The two error estimates of the ram force on die2d, against the true
error: the estimate from the cycles (Richardson, what the program prints as
+-) and the goal-oriented dual-weighted residual (Refinement/Dual-weighted
estimate: the adjoint with the contact states frozen, solved with velocity
degree + 1 on the same mesh). For each sequence and cycle: dofs, value, true
error, each estimate, and its effectivity (estimate / true error; 1 is
exact, below 1 the estimate misses part of the error).

Sequences: die2d with frictionless dies (Newtonian; a linear problem once
the contact states are fixed) for degrees 1 and 2, and N1 (Coulomb friction)
for degree 2, each Kelly-adaptive from the default deck's graded start
(fraction 0.5). The frictionless reference is the Richardson extrapolation
of the degree-2 frictionless sequence itself (printed); N1's is the
converged 2468.78 N/mm of benchmarks/die2d_runs.py.

    python3 benchmarks/die2d_estimates.py [--quick]

Not a test: run one benchmark at a time (about 2 minutes).
"""
import argparse

from die2d_runs import CONVERGED, MATERIAL, run_summary


def deck(output, degree, cycles, friction):
    return f"""set Output directory = {output}
set Write VTU = false
subsection Mesh
  set Corner refinements = 8
end
subsection Material
{MATERIAL["N1"]}end
subsection Contact
  set Friction coefficients = {friction}
end
subsection Discretisation
  set Velocity degree = {degree}
end
subsection Refinement
  set Cycles = {cycles}
  set Strategy = adaptive
  set Indicator = kelly
  set Refine fraction = 0.5
  set Dual-weighted estimate = true
end
"""


def run(**settings):
    summary = run_summary(deck, settings)
    rows = [dict(dofs=c["dofs"], value=c["quantities"]["F_x[1]"], time=c["wall_time"],
                 richardson=c["estimated_errors"].get("F_x[1]"), dwr=c["dual_weighted_error"])
            for c in summary["cycles"] if c["converged"]]
    return rows, summary.get("extrapolated", {}).get("F_x[1]")


def table(title, rows, reference):
    print(f"\n### {title}\n")
    print("| dofs | F_x[1] [N/mm] | true error F_h - F | from the cycles (+-) | effectivity "
          "| dual-weighted F_h - F | effectivity |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        error = r["value"] - reference
        richardson = "-" if r["richardson"] is None else f"{r['richardson']:.3f}"
        r_eff = "-" if r["richardson"] is None else f"{r['richardson'] / abs(error):.2f}"
        dwr = -r["dwr"]
        print(f"| {r['dofs']} | {r['value']:.3f} | {error:+.3f} | {richardson} | {r_eff} "
              f"| {dwr:+.3f} | {dwr / error:.2f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="fewer cycles")
    args = parser.parse_args()
    extra = 0 if args.quick else 3
    frictionless = "3: 0, 4: 0"
    q2, extrapolated = run(degree=2, cycles=6 + extra, friction=frictionless)
    reference = extrapolated["value"]
    print(f"frictionless reference (degree 2, Richardson over its last cycles): {reference:.3f} "
          f"+- {extrapolated['error']:.3f}")
    table("die2d, frictionless dies, degree 2, Kelly 0.5", q2, reference)
    q1, _ = run(degree=1, cycles=6 + extra, friction=frictionless)
    table("die2d, frictionless dies, degree 1, Kelly 0.5", q1, reference)
    n1, _ = run(degree=2, cycles=6 + extra, friction="3: 0.001, 4: 0.1")
    table(f"die2d N1 (Coulomb friction), degree 2, Kelly 0.5 (reference {CONVERGED['N1']})", n1, CONVERGED["N1"])


if __name__ == "__main__":
    main()
