#!/usr/bin/env python3
"""The round bar of parameters/roundbar-held-land.prm as a 3D quarter model (Mesh/Source
= round bar quarter, degree 2, one cycle, no corner refinement) on graded
meshes (Mesh/Die2d/Grading exponent), against the axisymmetric run on the
die2d meshes of the same grading and Cells across, and both against the
converged axisymmetric value 998.6 MPa (the round bar's reference,
1,132,536 N over pi 19^2, doc/axisymmetric.md "Time against error"). Mean axial stress F_x/A over the discrete inlet area.

    python3 benchmarks/roundbar3d.py [--program build/dieflow] [--across 4 8 16] [--grading 2.5]
                                      [--direct-limit 60000]

The issue's target: the quarter model within 1 % of the axisymmetric value
in at most 5 minutes on this 2-core machine. The direct solver is run up to
--direct-limit unknowns. Not a test: the times are this machine's (run one
benchmark at a time).
"""
import argparse, os, platform, re, tempfile

from deck_variant import run_variant

CONVERGED_MPA = 1132536.2 / (3.141592653589793 * 19 ** 2)


def deck_3d(grading, method):
    """roundbar-held-land.prm turned into the quarter model, as doc/three-dimensional.md says."""
    text = open("parameters/roundbar-held-land.prm").read()
    for old, new in [("set Dimension        = 2", "set Dimension = 3"),
                     ("set Geometry         = axisymmetric", "set Geometry = plane strain"),
                     ("set Source             = die2d", "set Source = round bar quarter"),
                     ("set Velocity = 190; 0", "set Velocity = 190; 0; 0"),
                     ("set Method = Newton", "set Method = Newton\nend\nsubsection Linear solver\n  set Method = " + method)]:
        assert old in text, old
        text = text.replace(old, new)
    return with_grading(text, grading)


def with_grading(text, grading):
    return re.sub(r"(set Cells across\s*=.*)", r"\1\n    set Grading exponent = %g" % grading, text)


def run(program, text, across):
    with tempfile.NamedTemporaryFile("w", suffix=".prm", delete=False) as deck:
        deck.write(text)
    status, s = run_variant(program, deck.name, {"Cells across": "%d" % across, "Corner refinements": "0",
                                                 "Cycles": "1"})
    os.unlink(deck.name)
    c = s["cycles"][-1]
    return status, s, c


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--program", default="build/dieflow")
    parser.add_argument("--across", type=int, nargs="+", default=[4, 8, 16])
    parser.add_argument("--grading", type=float, default=2.5)
    parser.add_argument("--direct-limit", type=int, default=60000)
    args = parser.parse_args()
    print("machine:", platform.processor() or platform.machine(), os.cpu_count(), "cores")
    print("grading exponent q = %g; converged axisymmetric mean axial stress %.1f MPa" % (args.grading, CONVERGED_MPA))
    print()
    print("| cells across | model | unknowns | solver | wall time [s] | peak memory [MB] | Newton its "
          "| F_x/A [MPa] | error |")
    print("|---|---|---|---|---|---|---|---|---|")
    for across in args.across:
        axi_text = with_grading(open("parameters/roundbar-held-land.prm").read(), args.grading)
        status, s, c = run(args.program, axi_text, across)
        stress = c["quantities"]["F_x[1]"] / c["boundary_area"]["1"]
        print("| %d | axisymmetric | %d | %s%s | %.1f | %.0f | %d | %.1f | %+.2f %% |"
              % (across, c["dofs"], c["linear_solver"]["method"], "" if status == 0 else " (exit %d)" % status,
                 s["wall_time"], s["peak_memory_mb"], c["nonlinear_iterations"], stress,
                 100 * (stress / CONVERGED_MPA - 1)))
        dofs = None
        for method in ["iterative", "direct"]:
            if method == "direct" and dofs is not None and dofs > args.direct_limit:
                print("| %d | 3D quarter | %d | direct | (skipped: above %d unknowns) | | | | |"
                      % (across, dofs, args.direct_limit))
                continue
            status, s, c = run(args.program, deck_3d(args.grading, method), across)
            stress = c["quantities"]["F_x[1]"] / c["boundary_area"]["1"]  # the polygonal section's area
            dofs = c["dofs"]
            print("| %d | 3D quarter | %d | %s%s | %.1f | %.0f | %d | %.1f | %+.2f %% |"
                  % (across, dofs, c["linear_solver"]["method"], "" if status == 0 else " (exit %d)" % status,
                     s["wall_time"], s["peak_memory_mb"], c["nonlinear_iterations"], stress,
                     100 * (stress / CONVERGED_MPA - 1)), flush=True)


if __name__ == "__main__":
    main()
