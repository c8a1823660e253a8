#!/usr/bin/env python3
"""Velocity degree 1 (Q1-P0, the paper's element) against degree 2
(Q2-P1disc) on die2d: ram-force error against dofs and cumulative wall time
of one run, Kelly-adaptive cycles from graded starts (Mesh/Corner
refinements), for N1 and P1. Errors are against the converged ram force
(N1: 2468.78 +- 0.05 N/mm since 2026-11-24, before 2468.6 +- 0.6; see
benchmarks/die2d_runs.py;
which the degree-2 sequence here confirms by extrapolation; P1: 82.66 +-
0.10). Prints one table per sequence (dofs, cumulative time, value, error,
the estimated error the program prints, Newton iterations), and the dofs and
time each sequence needs for 1 %, 0.1 %, 0.05 % and 0.01 %. The last N1/P1
sequences weight Kelly up at the die (Refinement/Indicator = combined): the
error the Kelly sequences leave is at the die wall; or aim at the ram force
(Indicator = dual weighted, goal-oriented). The last two start from the
ungraded mesh (Corner refinements = 0): does the indicator make up for the
grading?

    python3 benchmarks/die2d_degree.py [--case N1|P1] [--quick]

Not a test: the times are this machine's (run one benchmark at a time).
"""
import argparse

from die2d_runs import CONVERGED, MATERIAL, reach_table, reached, run as run_deck, table

LEVELS = (0.01, 0.001, 0.0005, 0.0001)


def deck(case, degree, across, corner_levels, cycles, marking, fraction, output, indicator="kelly", die_weight=1):
    return f"""set Output directory = {output}
set Write VTU = false
subsection Mesh
  set Corner refinements = {corner_levels}
  subsection Die2d
    set Cells across = {across}
  end
end
subsection Material
{MATERIAL[case]}end
subsection Discretisation
  set Velocity degree = {degree}
end
subsection Refinement
  set Cycles = {cycles}
  set Strategy = adaptive
  set Indicator = {indicator}
  set Die weight = {die_weight}
  set Marking = {marking}
  set Refine fraction = {fraction}
end
"""


def run(case, **settings):
    return run_deck(lambda **kw: deck(case, **kw), settings)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--case", default="N1", choices=sorted(CONVERGED))
    parser.add_argument("--quick", action="store_true", help="fewer cycles")
    args = parser.parse_args()
    converged = CONVERGED[args.case]
    extra = 0 if args.quick else 4

    sequences = [
        ("degree 1, 8 across, 5 corner levels, Kelly fraction 0.5 (the degree-1 recipe)",
         dict(degree=1, across=8, corner_levels=5, marking="fixed fraction", fraction=0.5, cycles=6 + extra)),
        ("degree 2, 8 across, 5 corner levels, Kelly fraction 0.5",
         dict(degree=2, across=8, corner_levels=5, marking="fixed fraction", fraction=0.5, cycles=8 + extra)),
        ("degree 2, 8 across, 8 corner levels, Kelly fraction 0.5 (the default deck, which stops at the fourth cycle)",
         dict(degree=2, across=8, corner_levels=8, marking="fixed fraction", fraction=0.5, cycles=9 + extra)),
        ("degree 2, 8 across, 8 corner levels, combined indicator (Kelly x (1 + 3 x die criterion)), fraction 0.5",
         dict(degree=2, across=8, corner_levels=8, marking="fixed fraction", fraction=0.5, cycles=10 + extra,
              indicator="combined", die_weight=3)),
        ("degree 2, 8 across, 8 corner levels, dual-weighted indicator (Kelly of v x Kelly of the ram force's dual), fixed number 0.15",
         dict(degree=2, across=8, corner_levels=8, marking="fixed number", fraction=0.15, cycles=7 + extra,
              indicator="dual weighted")),
        ("degree 2, 8 across, no grading (any start), Kelly fraction 0.5",
         dict(degree=2, across=8, corner_levels=0, marking="fixed fraction", fraction=0.5, cycles=12 + extra)),
        ("degree 2, 8 across, no grading (any start), dual-weighted indicator, fixed fraction 0.9",
         dict(degree=2, across=8, corner_levels=0, marking="fixed fraction", fraction=0.9, cycles=17 + extra,
              indicator="dual weighted")),
    ]
    summary = []
    for title, settings in sequences:
        rows, extrapolated = run(args.case, **settings)
        table(f"{args.case}, {title}", rows, converged, digits=3)
        if extrapolated:
            print(f"\nextrapolated from the last three cycles: {extrapolated['value']:.3f} "
                  f"+- {extrapolated['error']:.3f} (order {extrapolated['order']:.2f} in N)")
        summary.append((title, [reached(rows, converged, level) for level in LEVELS]))
    reach_table(args.case, summary, LEVELS)


if __name__ == "__main__":
    main()
