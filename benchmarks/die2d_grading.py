#!/usr/bin/env python3
"""The die2d mesh at the die corners: ram-force error against dofs and
cumulative wall time for
  - the two block layouts of the built-in mesh (blocks: joined along the
    verticals through C and D; bisected: along the corners' bisectors) on
    uniform meshes,
  - geometric grading towards the wall corners (Mesh/Corner refinements),
  - Kelly-adaptive cycles from the old built-in start, from the bisected
    start, and from the graded start of the default deck,
for die2d N1 (and P1 with --case P1). Errors are against the converged ram
force (N1: 2468.78 +- 0.05 N/mm since 2026-11-24, before 2468.6 +- 0.6,
see benchmarks/die2d_runs.py; the 2.6M-dof degree-1 run of
doc/benchmarks.md; P1: 82.66 +- 0.10). Prints one table per sequence, the
estimated error the program prints (the +- of the screen summary), and the
dofs and time each sequence needs for 1 %, 0.2 % and 0.1 %.

    python3 benchmarks/die2d_grading.py [--case N1|P1] [--quick]

Not a test: the times are this machine's (run one benchmark at a time).
"""
import argparse

from die2d_runs import CONVERGED, MATERIAL, reached, run as run_deck, table


def deck(case, layout, across, corner_levels, cycles, strategy, fraction, output):
    return f"""set Output directory = {output}
set Write VTU = false
subsection Mesh
  set Corner refinements = {corner_levels}
  subsection Die2d
    set Layout = {layout}
    set Cells across = {across}
  end
end
subsection Material
{MATERIAL[case]}end
subsection Refinement
  set Cycles = {cycles}
  set Strategy = {strategy}
  set Indicator = kelly
  set Refine fraction = {fraction}
end
"""


def run(case, **settings):
    return run_deck(lambda **kw: deck(case, **kw), settings)[0]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--case", default="N1", choices=sorted(CONVERGED))
    parser.add_argument("--quick", action="store_true", help="fewer and smaller runs")
    args = parser.parse_args()
    converged = CONVERGED[args.case]

    single = lambda layout, across, levels: run(args.case, layout=layout, across=across, corner_levels=levels,
                                                cycles=1, strategy="global", fraction=0.3)[0]
    sizes = [8, 16, 32] if args.quick else [8, 16, 32, 64]
    for layout in ("blocks", "bisected"):
        table(f"{args.case}, layout {layout}, uniform meshes (8, 16, 32, ... cells across)",
              [single(layout, n, 0) for n in sizes], converged)
    table(f"{args.case}, bisected, 8 cells across, Corner refinements 0, 1, 3, 5, 7 (width 1)",
          [single("bisected", 8, k) for k in (0, 1, 3, 5, 7)], converged)

    cycles = 6 if args.quick else 8
    sequences = [
        ("adaptive Kelly from the old built-in start (blocks, 4 across, fraction 0.3)",
         dict(layout="blocks", across=4, corner_levels=0, fraction=0.3, cycles=cycles + 6)),
        ("adaptive Kelly from the bisected start (8 across, fraction 0.5)",
         dict(layout="bisected", across=8, corner_levels=0, fraction=0.5, cycles=cycles)),
        ("adaptive Kelly from the graded start (bisected, 8 across, 5 corner levels, fraction 0.5): the degree-1 recipe",
         dict(layout="bisected", across=8, corner_levels=5, fraction=0.5, cycles=cycles)),
    ]
    summary = []
    for title, settings in sequences:
        rows = run(args.case, strategy="adaptive", **settings)
        table(f"{args.case}, {title}", rows, converged)
        summary.append((title, [reached(rows, converged, level) for level in (0.01, 0.002, 0.001)]))
    print(f"\n### {args.case}: dofs / cumulative wall time to reach the error\n")
    print("| sequence | 1 % | 0.2 % | 0.1 % |")
    print("|---|---|---|---|")
    for title, cells in summary:
        print(f"| {title} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
